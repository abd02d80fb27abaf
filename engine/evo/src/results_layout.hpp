// Names shared by the results writer and reader (internal); the layout is documented in
// docs/results-format.md.
#pragma once

#include <string>

#include "plastivox/evo/run_state.hpp"
#include "plastivox/io/h5_util.hpp"

namespace plastivox::evo::layout {

inline constexpr const char* kFormat = "plastivox-evolution";
inline const char* const kNetworkNames[kNetworkCount] = {"geometry", "stiffness", "development",
                                                         "phase"};

// "000042": champion group names sort in order of appearance.
std::string champion_name(size_t k);

// A hash of what a resumed run needs beyond the science (cache, bookkeeping), so a
// corrupted checkpoint is refused instead of silently changing the continuation.
Hash128 checkpoint_digest(const RunState& s);

}  // namespace plastivox::evo::layout
