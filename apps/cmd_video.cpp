// plastivox video: placeholder until its owner lands it (session 2 work in progress).
#include <stdexcept>

#include "cli.hpp"

namespace plastivox::cli {

int cmd_video(const Args&) { throw std::runtime_error("'video' is not built yet"); }

}  // namespace plastivox::cli
