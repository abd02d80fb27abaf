// Number formatting and atomic files for the study's outputs (over the engine's
// write_file_atomic).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "plastivox/io/atomic_file.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {

std::string number(double x) {
  if (!std::isfinite(x)) return "";
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

std::string number(const std::optional<double>& x) {
  return x ? number(*x) : "";
}

std::string display(double x, int digits) {
  if (!std::isfinite(x)) return "–";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

std::string display(const std::optional<double>& x, int digits) {
  return x ? display(*x, digits) : "–";
}

void write_temp(const std::string& path, const std::string& text) {
  check_output_path(path);                 // the temporary is renamed over it later
  write_file_atomic(path + ".tmp", text);  // complete and flushed under the temporary name
}

void commit_temp(const std::string& path) {
  std::error_code ec;
  std::filesystem::rename(path + ".tmp", path, ec);
  if (ec) throw std::runtime_error(path + ": cannot rename " + path + ".tmp: " + ec.message());
}

void sync_file(const std::string& path, const std::string& for_file) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  const bool ok = fd >= 0 && ::fsync(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw std::runtime_error(for_file + ": cannot sync " + path + ": " + std::strerror(err));
}

void write_atomically(const std::string& path, const std::string& text) {
  write_file_atomic(path, text);
}

}  // namespace plastivox::analysis::study
