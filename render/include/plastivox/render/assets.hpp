// Where the renderer finds its data files (shaders, viewer scripts, fonts): $PLASTIVOX_ASSETS
// if set, else share/plastivox/assets in the nearest folder above the program or Python module
// that holds it, so nothing depends on where the build ran: <prefix>/share/plastivox/assets
// for `cmake --install` (program in <prefix>/bin), the package's own share/plastivox/assets in
// a wheel, and <build>/share/plastivox/assets in a build tree (a link CMake makes to assets/).
#pragma once

#include <string>

namespace plastivox::render {

// The assets directory. Throws RenderError (one line naming where it looked and the
// environment variable) if no such directory holds shaders/.
std::string assets_dir();

// Reads assets_dir()/relative as text; throws RenderError naming the file.
std::string read_asset(const std::string& relative);

}  // namespace plastivox::render
