// A counting allocator for the memory tests: counting_new.cpp replaces the global operator new
// and delete of the test binary it is linked into, and keeps the live and peak heap bytes
// (every std container allocates there). Thread-safe: the gradient's backward pass may run a
// second thread.
#pragma once

#include <cstddef>

namespace plastivox::test {

// The peak of live heap bytes since it was constructed, above what was live then.
class PeakScope {
 public:
  PeakScope();
  size_t peak() const;

 private:
  size_t base_;
};

}  // namespace plastivox::test
