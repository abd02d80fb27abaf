#include "plastivox/render/assets.hpp"

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/error.hpp"

namespace plastivox::render {
namespace fs = std::filesystem;

namespace {

bool holds_shaders(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "shaders", ec);
}

// The path of the file this function was linked into: the Python module's shared object (its
// link map names it), or else the program, whose link map has an empty name and whose own path
// the kernel keeps in /proc/self/exe (dladdr would give argv[0], maybe not a path at all).
std::string loaded_file_path() {
  Dl_info info{};
  void* map_ptr = nullptr;
  if (dladdr1(reinterpret_cast<void*>(&loaded_file_path), &info, &map_ptr, RTLD_DL_LINKMAP)) {
    const auto* map = static_cast<const link_map*>(map_ptr);
    if (map && map->l_name && *map->l_name) {
      std::error_code ec;
      const fs::path p = fs::weakly_canonical(map->l_name, ec);
      return ec ? std::string(map->l_name) : p.string();
    }
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.string();
}

}  // namespace

std::string assets_dir() {
  if (const char* env = std::getenv("PLASTIVOX_ASSETS"); env && *env) {
    if (!holds_shaders(env))
      throw RenderError(std::string("assets directory ") + env +
                        " has no shaders/ (from PLASTIVOX_ASSETS): set PLASTIVOX_ASSETS to the "
                        "plastivox assets/ directory");
    return env;
  }
  const std::string self = loaded_file_path();
  if (!self.empty()) {
    for (fs::path dir = fs::path(self).parent_path(); !dir.empty(); dir = dir.parent_path()) {
      const fs::path candidate = dir / "share" / "plastivox" / "assets";
      if (holds_shaders(candidate)) return candidate.string();
      if (dir == dir.root_path()) break;
    }
  }
  throw RenderError("no share/plastivox/assets with shaders/ in any folder above " +
                    (self.empty() ? std::string("this program (its path is unknown)") : self) +
                    ": set PLASTIVOX_ASSETS to the plastivox assets/ directory");
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
