// The commit the sources were at when this binary was built (provenance.hpp). Its header is
// rewritten by every build whose commit differs (cmake/commit_stamp.cmake), so this file, kept
// out of the unity batches, is all that recompiles after a commit or a first edit.
#include "plastivox/io/provenance.hpp"
#include "plastivox_commit.hpp"

namespace plastivox {

const char* build_git_commit() {
  return PLASTIVOX_BUILD_GIT_COMMIT;
}

}  // namespace plastivox
