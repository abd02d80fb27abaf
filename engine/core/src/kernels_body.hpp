// Every kernel body, and the KernelSet (kernels.hpp) of lane type T (tails in double): what
// kernels.cpp compiles for `double` and each instruction set's file for its vector type.
#pragma once

#include "bond_body.hpp"
#include "contact_body.hpp"
#include "develop_body.hpp"
#include "kernels.hpp"
#include "voxel_body.hpp"

namespace plastivox {
namespace {

template <class T>
KernelSet make_kernel_set() {
  return KernelSet{&run_bonds<T>,   &run_gather<T>,  &run_update<T>,      &run_sine<T>,
                   &run_actuate<T>, &run_develop<T>, &run_scan_within<T>, &run_touch_candidates<T>};
}

}  // namespace
}  // namespace plastivox
