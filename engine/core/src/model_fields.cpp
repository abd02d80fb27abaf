// The Model's table (plastivox/model_fields.hpp).
#include "plastivox/model_fields.hpp"

#include <stdexcept>
#include <string>

namespace plastivox {
namespace {

using fields::bytes_of;

// A row of one Model member, its bytes as bytes_of gives them.
#define PLASTIVOX_MODEL_ROW(name, member, shape, unit, frame, meaning)                   \
  {                                                                                      \
    name, shape, unit, frame, meaning, [](const Model& m) { return bytes_of(m.member); } \
  }

// The six bond slots of each voxel, one int per face.
StateFieldBytes voxel_bonds(const Model& m) {
  static_assert(sizeof(std::array<int, 6>) == 6 * sizeof(int));
  return {m.voxel_bonds.data(), m.voxel_bonds.size() * 6, sizeof(int), 'i', 6};
}

}  // namespace

const std::vector<ModelField> kModelFields = {
    PLASTIVOX_MODEL_ROW("n", n, "1", "1", "-", "voxels: the robot's, then the free objects'"),
    PLASTIVOX_MODEL_ROW("robot_n", robot_n, "1", "1", "-", "the robot's voxels, the first ones"),
    PLASTIVOX_MODEL_ROW("object_begin", object_begin, "objects + 1", "1", "-",
                        "each free object's first voxel, then n"),
    PLASTIVOX_MODEL_ROW("size", size, "1", "m", "-", "nominal voxel edge length L"),
    PLASTIVOX_MODEL_ROW("mass", mass, "1", "kg", "-", "mass of a voxel"),
    PLASTIVOX_MODEL_ROW("inertia", inertia, "1", "kg m^2", "-",
                        "moment of inertia of a voxel about a centre axis"),
    PLASTIVOX_MODEL_ROW("k_area", k.area, "1", "m^2", "-", "axial stiffness per modulus (L^2)"),
    PLASTIVOX_MODEL_ROW("k_inv_L", k.inv_L, "1", "1/m", "-", "1 / L"),
    PLASTIVOX_MODEL_ROW("k_ka2", k.ka2, "1", "m^3", "-",
                        "torsion stiffness per modulus (L^3 / (12 (1 + nu)))"),
    PLASTIVOX_MODEL_ROW("k_kb1", k.kb1, "1", "m", "-", "shear stiffness per modulus (L)"),
    PLASTIVOX_MODEL_ROW("k_kb2", k.kb2, "1", "m^2", "-",
                        "shear-rotation coupling per modulus (L^2 / 2)"),
    PLASTIVOX_MODEL_ROW("k_kb3", k.kb3, "1", "m^3", "-", "bending stiffness per modulus (L^3 / 6)"),
    PLASTIVOX_MODEL_ROW("k_bond_damp", k.bond_damp, "1", "kg^0.5", "-",
                        "bond damping: 2 sqrt(m) zeta_bond"),
    PLASTIVOX_MODEL_ROW("k_damp_a1", k.damp_a1, "1", "m^0.5", "-",
                        "axial and shear damping per sqrt(E) (sqrt(L))"),
    PLASTIVOX_MODEL_ROW("k_damp_b2", k.damp_b2, "1", "m^1.5", "-",
                        "shear-rotation damping per sqrt(E) (sqrt(L^3 / 4))"),
    PLASTIVOX_MODEL_ROW("k_damp_a2", k.damp_a2, "1", "m^2.5", "-",
                        "torsion damping per sqrt(E) (sqrt(L^5 / (72 (1 + nu))))"),
    PLASTIVOX_MODEL_ROW("k_damp_b3", k.damp_b3, "1", "m^2.5", "-",
                        "bending damping per sqrt(E) (sqrt(L^5 / 36))"),
    PLASTIVOX_MODEL_ROW("k_c_lin_unit", k.c_lin_unit, "1", "kg^0.5 m^0.5", "-",
                        "linear voxel damping per sqrt(E) (2 sqrt(m L))"),
    PLASTIVOX_MODEL_ROW("k_c_rot_unit", k.c_rot_unit, "1", "kg^0.5 m^2.5", "-",
                        "rotational voxel damping per sqrt(E) (2 sqrt(I L^3))"),
    PLASTIVOX_MODEL_ROW("site", site, "n", "1", "-", "lattice site of the voxel (-1: an object's)"),
    PLASTIVOX_MODEL_ROW("rest_pos", rest_pos, "n x 3", "m", "world", "initial voxel centre"),
    PLASTIVOX_MODEL_ROW("e0", e0, "n", "Pa", "-", "congenital Young's modulus"),
    PLASTIVOX_MODEL_ROW("alpha", alpha, "n", "1/s", "-", "development rate"),
    PLASTIVOX_MODEL_ROW("phase", phase, "n", "cycles", "-", "actuation phase"),
    PLASTIVOX_MODEL_ROW("act_gain", act_gain, "n", "1", "-",
                        "actuation amplitude factor (times act_scale)"),
    PLASTIVOX_MODEL_ROW("act_per_voxel", act_per_voxel, "1", "-", "-",
                        "act_gain is the robot's own amplitude (voxcraft's rule)"),
    PLASTIVOX_MODEL_ROW("act_amplitude_max", act_amplitude_max, "1", "1", "-",
                        "the largest linear amplitude any voxel can reach"),
    {"voxel_bonds", "n x 6", "1", "-", "bond of each face (-x, +x, -y, +y, -z, +z; -1: none)",
     voxel_bonds},
    PLASTIVOX_MODEL_ROW("fixed", fixed, "n", "-", "-", "1 if clamped"),
    PLASTIVOX_MODEL_ROW("load", load, "n x 3", "N", "world", "constant external force"),
    PLASTIVOX_MODEL_ROW("surface", surface, "n", "-", "-", "1 if some face has no neighbour"),
    PLASTIVOX_MODEL_ROW("bond_a", bond_a, "bonds", "1", "-", "voxel on the bond's negative side"),
    PLASTIVOX_MODEL_ROW("bond_b", bond_b, "bonds", "1", "-", "voxel on the bond's positive side"),
    PLASTIVOX_MODEL_ROW("bond_axis", bond_axis, "bonds", "-", "-",
                        "the bond's axis (0 x, 1 y, 2 z)"),
    PLASTIVOX_MODEL_ROW("terrain", terrain, "1", "-", "-",
                        "contact takes the environment's ground (else the floor z = 0)"),
};

const ModelField& model_field(std::string_view name) {
  for (const ModelField& f : kModelFields)
    if (name == f.name) return f;
  throw std::invalid_argument("no Model field is called " + std::string(name));
}

}  // namespace plastivox
