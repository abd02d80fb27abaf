// Shared by the voxcraft-sim reader and writer (voxcraft_read.cpp, voxcraft_write.cpp).
#pragma once

#include <vector>

#include "plastivox/robot.hpp"

namespace plastivox {

// sqrt(k_bond / k_top) for the robot's voxels with modulus e[site] (Pa, per lattice site):
// k_bond the stiffest bond's harmonic-mean E (voxcraft-sim's time step), k_top the stiffest
// voxel's E (plastivox's), so voxcraft's DtFrac = plastivox's dt_frac x this ratio gives both
// simulators the same dt. 1 for a robot without bonds (voxcraft then takes the voxels too).
double voxcraft_dt_ratio(const RobotDef& robot, const std::vector<double>& e);

}  // namespace plastivox
