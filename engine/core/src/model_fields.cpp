// The Model's table (plastivox/model_fields.hpp).
#include "plastivox/model_fields.hpp"

#include <stdexcept>
#include <string>

namespace plastivox {
namespace {

using fields::bytes_of;

// A row of one Model member, its bytes as bytes_of gives them.
#define PLASTIVOX_MODEL_ROW(name, member, shape, unit, axes, meaning)                   \
  {                                                                                     \
    name, shape, unit, axes, meaning, [](const Model& m) { return bytes_of(m.member); } \
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
    PLASTIVOX_MODEL_ROW("inv_mass", inv_mass, "1", "1/kg", "-", "1 / mass"),
    PLASTIVOX_MODEL_ROW("inv_inertia", inv_inertia, "1", "1/(kg m^2)", "-", "1 / inertia"),
    PLASTIVOX_MODEL_ROW("inv_volume", inv_volume, "1", "1/m^3", "-", "1 / L^3"),
    PLASTIVOX_MODEL_ROW("area", area, "1", "m^2", "-", "axial stiffness per modulus (L^2)"),
    PLASTIVOX_MODEL_ROW("inv_L", inv_L, "1", "1/m", "-", "1 / L"),
    PLASTIVOX_MODEL_ROW("ka2", ka2, "1", "m^3", "-",
                        "torsion stiffness per modulus (L^3 / (12 (1 + nu)))"),
    PLASTIVOX_MODEL_ROW("kb1", kb1, "1", "m", "-", "shear stiffness per modulus (L)"),
    PLASTIVOX_MODEL_ROW("kb2", kb2, "1", "m^2", "-",
                        "shear-rotation coupling per modulus (L^2 / 2)"),
    PLASTIVOX_MODEL_ROW("kb3", kb3, "1", "m^3", "-", "bending stiffness per modulus (L^3 / 6)"),
    PLASTIVOX_MODEL_ROW("bond_damp", bond_damp, "1", "kg^0.5", "-",
                        "bond damping: 2 sqrt(m) zeta_bond"),
    PLASTIVOX_MODEL_ROW("damp_a1", damp_a1, "1", "m^0.5", "-",
                        "axial and shear damping per sqrt(E) (sqrt(L))"),
    PLASTIVOX_MODEL_ROW("damp_b2", damp_b2, "1", "m^1.5", "-",
                        "shear-rotation damping per sqrt(E) (sqrt(L^3 / 4))"),
    PLASTIVOX_MODEL_ROW("damp_a2", damp_a2, "1", "m^2.5", "-",
                        "torsion damping per sqrt(E) (sqrt(L^5 / (72 (1 + nu))))"),
    PLASTIVOX_MODEL_ROW("damp_b3", damp_b3, "1", "m^2.5", "-",
                        "bending damping per sqrt(E) (sqrt(L^5 / 36))"),
    PLASTIVOX_MODEL_ROW(
        "axial_own", axial_own, "1", "-", "-",
        "a bond's axial stress from voxel a's own modulus (negative-voxel stimulus)"),
    PLASTIVOX_MODEL_ROW("min_shear_chord", min_shear_chord, "1", "m", "-",
                        "floor of the chord in the exact model's shear coupling"),
    PLASTIVOX_MODEL_ROW("c_lin_unit", c_lin_unit, "1", "kg^0.5 m^0.5", "-",
                        "linear voxel damping per sqrt(E) (2 sqrt(m L))"),
    PLASTIVOX_MODEL_ROW("c_rot_unit", c_rot_unit, "1", "kg^0.5 m^2.5", "-",
                        "rotational voxel damping per sqrt(E) (2 sqrt(I L^3))"),
    PLASTIVOX_MODEL_ROW("c_col_unit", c_col_unit, "1", "kg^0.5 m^0.5", "-",
                        "floor contact damping per sqrt(E) (collision_damping c_lin_unit)"),
    PLASTIVOX_MODEL_ROW("rot_damp", rot_damp, "1", "1", "-",
                        "rotational slow damping over the linear one's ratio"),
    PLASTIVOX_MODEL_ROW("weight", weight, "3", "N", "-", "m g, world axes"),
    PLASTIVOX_MODEL_ROW("flat_floor", flat_floor, "1", "-", "-",
                        "the update kernel's floor z = 0 (floor without an environment's ground)"),
    PLASTIVOX_MODEL_ROW("pressure_denominator", pressure_denominator, "1", "1", "-",
                        "the pressure stimulus's denominator 3 (1 - 2 nu)"),
    PLASTIVOX_MODEL_ROW("gate", gate, "1", "Pa", "-",
                        "min_devo_factor e_min: a voxel below it does not develop"),
    PLASTIVOX_MODEL_ROW("act_amplitude_xi", act_amplitude_xi, "1", "1", "-",
                        "actuation amplitude in xi(E) gain u"),
    PLASTIVOX_MODEL_ROW("xi_e_max", xi_e_max, "1", "Pa", "-",
                        "xi(E) = (xi_e_max - E) xi_inv_range + xi_base"),
    PLASTIVOX_MODEL_ROW("xi_inv_range", xi_inv_range, "1", "1/Pa", "-", "xi(E)'s slope"),
    PLASTIVOX_MODEL_ROW("xi_base", xi_base, "1", "1", "-", "xi(E)'s base"),
    PLASTIVOX_MODEL_ROW("act_wave_max", act_wave_max, "1", "1", "-",
                        "largest signal the actuation takes (+inf, or 0 without act_expansion)"),
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
