#include "plastivox/io/provenance.hpp"

#include <unistd.h>

#include <cstdio>

#include "build_info.hpp"
#include "plastivox/base/clock.hpp"

namespace plastivox {

Provenance current_provenance(int threads) {
  Provenance p;
  p.plastivox_version = PLASTIVOX_BUILD_VERSION;
  p.git_commit = build_git_commit();
  p.compiler = PLASTIVOX_BUILD_COMPILER;
  p.compiler_flags = PLASTIVOX_BUILD_FLAGS;
  p.build_type = PLASTIVOX_BUILD_BUILD_TYPE;
  p.date_created = p.date_updated = utc_timestamp();
  char host[256] = "";
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "unknown");
  p.host = host;
  p.threads = threads;
  return p;
}

}  // namespace plastivox
