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
#include <fstream>
#include <sstream>
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

std::string bits(double x) {
  uint64_t u = 0;
  std::memcpy(&u, &x, sizeof u);
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(u));
  return buf;
}

double from_bits(const std::string& s) {
  if (s.size() != 16) throw std::runtime_error("bad double bits");
  const uint64_t u = std::stoull(s, nullptr, 16);
  double x = 0;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

std::optional<nlohmann::ordered_json> read_checkpoint_json(const std::string& path,
                                                           const std::string& format,
                                                           const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    std::stringstream ss;
    ss << in.rdbuf();
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(ss.str());
    if (j.at("format") != format || j.at("version") != 1 || j.at("key") != key) return std::nullopt;
    return j;
  } catch (const std::exception&) {
    return std::nullopt;
  }
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
