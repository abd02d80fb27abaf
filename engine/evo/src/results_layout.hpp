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

// The columns of /individuals stored as the record holds them, as f(name, member); the writer
// and the reader both walk this list. `id` (checked on reading), `sank` (absent in older files)
// and the sparse failures are handled by each side.
template <class F>
void for_each_birth_column(F&& f) {
  f("parent_id", &BirthRecord::parent_id);
  f("generation", &BirthRecord::generation);
  f("fitness", &BirthRecord::fitness);
  f("status", &BirthRecord::status);
  f("voxels", &BirthRecord::voxels);
  f("tries", &BirthRecord::tries);
  f("simulated", &BirthRecord::simulated);
}

// The same for /checkpoint/population (`status`, an enum, and the genomes aside).
template <class F>
void for_each_member_column(F&& f) {
  f("id", &Individual::id);
  f("parent_id", &Individual::parent_id);
  f("age", &Individual::age);
  f("born", &Individual::born);
  f("fitness", &Individual::fitness);
}

// A hash of what a resumed run needs beyond the science (cache, bookkeeping), so a
// corrupted checkpoint is refused instead of silently changing the continuation.
Hash128 checkpoint_digest(const RunState& s);

}  // namespace plastivox::evo::layout
