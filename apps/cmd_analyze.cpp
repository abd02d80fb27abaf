// plastivox analyze: placeholder until its owner lands it (session 2 work in progress).
#include <stdexcept>

#include "cli.hpp"

namespace plastivox::cli {

int cmd_analyze(const Args&) { throw std::runtime_error("'analyze' is not built yet"); }

}  // namespace plastivox::cli
