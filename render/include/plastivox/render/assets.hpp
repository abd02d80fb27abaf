// Where the renderer finds its data files (shaders, fonts): $PLASTIVOX_ASSETS if set, else
// the source tree's assets/ directory as configured at build time.
#pragma once

#include <string>

namespace plastivox::render {

// The assets directory. Throws RenderError (one line naming the path and the environment
// variable) if the chosen directory does not hold shaders/.
std::string assets_dir();

// Reads assets_dir()/relative as text; throws RenderError naming the file.
std::string read_asset(const std::string& relative);

}  // namespace plastivox::render
