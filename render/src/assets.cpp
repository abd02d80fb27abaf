#include "plastivox/render/assets.hpp"

#include <cstdlib>
#include <filesystem>

#include "plastivox/atomic_file.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/robot_file.hpp"  // InputError

namespace plastivox::render {

std::string assets_dir() {
  const char* env = std::getenv("PLASTIVOX_ASSETS");
  const bool from_env = env && *env;
  const std::string dir = from_env ? std::string(env) : std::string(PLASTIVOX_ASSETS_DIR);
  std::error_code ec;
  if (!std::filesystem::is_directory(std::filesystem::path(dir) / "shaders", ec))
    throw RenderError("assets directory " + dir + " has no shaders/ (" +
                      (from_env ? "from PLASTIVOX_ASSETS" : "built-in default") +
                      "): set PLASTIVOX_ASSETS to the plastivox assets/ directory");
  return dir;
}

std::string read_asset(const std::string& relative) {
  const std::string path = assets_dir() + "/" + relative;
  try {
    return read_file_bytes(path);
  } catch (const InputError& e) {
    throw RenderError(std::string(e.what()) + " (asset file)");
  }
}

}  // namespace plastivox::render
