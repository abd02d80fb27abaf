// A KernelSet (kernels.hpp) of the lane-generic kernels for lane type T of width W, with
// tails in double. Included after every kernel body, by the files compiled for each
// instruction set.
#pragma once

#include "bond_lanes_body.hpp"
#include "contact_scan_body.hpp"
#include "develop_lanes_body.hpp"
#include "kernels.hpp"
#include "voxel_lanes_body.hpp"

namespace plastivox {
namespace {

template <class T, int W>
KernelSet make_kernel_set() {
  return KernelSet{&run_bond_lanes<T, W>,      &run_gather<T, W>,        &run_update_lanes<T, W>,
                   &run_actuate_lanes<T, W>,   &run_develop_lanes<T, W>, &run_scan_within<T, W>,
                   &run_touch_candidates<T, W>};
}

}  // namespace
}  // namespace plastivox
