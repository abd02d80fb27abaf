// A CMA-ES genome on its fixed body (docs/evolution.md, "CMA-ES"): which numbers of the body
// the vector sets, how, and where the search starts. The body's voxels are taken in site order.
//   controller  the weights of the body's distributed or central controller, as they are;
//   phase       each voxel's actuation phase, cycles, whole cycles off into (-1, 1);
//   materials   each voxel's stiffness E = e_min (e_max / e_min)^logistic(x), then (unless
//               the treatment is none, which ignores development) its development rate
//               alpha = -10 + 20 logistic(x) (the CPPN's, phenotype.hpp). Stiffness is on a
//               log scale, unlike the CPPN's linear map: E spans six decades, and linearly
//               every soft material would sit deep in the logistic's tail, where a step of
//               sigma changes nothing.
// The start is the body's own values (through the inverse mappings, clamped to |x| <= 30).
#pragma once

#include <vector>

#include "plastivox/evo/config.hpp"
#include "plastivox/evo/phenotype.hpp"

namespace plastivox::evo {

int genome_dimension(const EvolveConfig& c);
std::vector<double> genome_start(const EvolveConfig& c);
double default_sigma(GenomeKind g);  // controller 0.5, phase 0.25, materials 1

// The body with x applied: always valid (the body was), hashed like every phenotype.
Phenotype express_vector(const EvolveConfig& c, const std::vector<double>& x);

// The fixed body of a config's "body" field: a robot file, or a results file whose last
// champion it takes (InputError naming the field).
RobotDef read_body(const std::string& path, const std::string& source);

}  // namespace plastivox::evo
