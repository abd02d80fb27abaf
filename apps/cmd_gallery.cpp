// plastivox gallery: placeholder until its owner lands it (session 2 work in progress).
#include <stdexcept>

#include "cli.hpp"

namespace plastivox::cli {

int cmd_gallery(const Args&) { throw std::runtime_error("'gallery' is not built yet"); }

}  // namespace plastivox::cli
