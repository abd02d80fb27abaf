// The compiled Model's numbers as a table (name, shape, unit, axes, meaning, and where the
// bytes are), as State's table (kStateFields) describes the state: what Python's
// Simulator.model shows and docs/engine.md, "Model", lists. Every number and array of Model
// is a row, but what other tables or files give: the physics (Model::def, PhysicsDef's
// fields), the controller (its kind, size and weights: the robot's), the ground's height field
// (the environment) and each voxel's list of neighbours that never collide (near_voxels, of
// varying length). Shapes as State's, and "n x 6" a bond slot per face, "objects + 1" one more
// than the free objects.
#pragma once

#include <string_view>
#include <vector>

#include "plastivox/field_table.hpp"
#include "plastivox/model.hpp"

namespace plastivox {

using ModelField = FieldRow<Model>;
extern const std::vector<ModelField> kModelFields;
// The row of kModelFields called `name`; std::invalid_argument for a name not in it.
const ModelField& model_field(std::string_view name);

}  // namespace plastivox
