#include "plastivox/base/output_path.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include "plastivox/base/error.hpp"

namespace plastivox {

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  std::error_code ec;
  if (p.has_parent_path() && !fs::is_directory(p.parent_path(), ec))
    throw InputError(path + ": cannot write: folder " + p.parent_path().string() +
                     " does not exist");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  throw InputError(
      path + ": " +
      (S_ISDIR(st.st_mode) ? "is a folder" : "is not a regular file (a device, pipe or socket)") +
      "; refusing to replace it with an output file");
}

void remove_stale_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  const std::string prefix = p.filename().string() + ".tmp.";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string pid = name.substr(prefix.size());
    if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos)
      continue;  // not a temporary of ours (pids have at most 7 digits)
    const long id = std::stol(pid);
    if (id == ::getpid() || ::kill(static_cast<pid_t>(id), 0) == 0 || errno != ESRCH) continue;
    std::error_code rm;
    fs::remove(e.path(), rm);
  }
}

}  // namespace plastivox
