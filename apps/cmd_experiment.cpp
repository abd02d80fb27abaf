// plastivox experiment: placeholder until its owner lands it (session 2 work in progress).
#include <stdexcept>

#include "cli.hpp"

namespace plastivox::cli {

int cmd_experiment(const Args&) { throw std::runtime_error("'experiment' is not built yet"); }

}  // namespace plastivox::cli
