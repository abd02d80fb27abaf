#include "plastivox/base/output_path.hpp"

#include <sys/stat.h>

#include "plastivox/base/error.hpp"

namespace plastivox {

void check_output_path(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  throw InputError(
      path + ": " +
      (S_ISDIR(st.st_mode) ? "is a folder" : "is not a regular file (a device, pipe or socket)") +
      "; refusing to replace it with an output file");
}

}  // namespace plastivox
