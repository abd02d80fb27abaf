// Atomic whole-file writes (temporary + rename) and whole-file reads.
#include "plastivox/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "plastivox/base/error.hpp"  // InputError

namespace plastivox {

void write_file_atomic(const std::string& path, std::string_view bytes) {
  check_output_path(path);
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() &&
                       std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !written) {
    std::remove(tmp.c_str());
    throw InputError(path + ": write failed (" + std::strerror(written ? errno : err) + ")");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot move the finished file into place: " + ec.message());
  }
  // The rename is durable only once the folder is synced. A file system that cannot sync a
  // folder says so with EINVAL (or ENOTSUP) and is let be; any other failure (an I/O error)
  // means the new file may not survive a crash, and is reported.
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const int rc = fd < 0 ? -1 : ::fsync(fd);
  const int sync_err = errno;
  if (fd >= 0) ::close(fd);
  if (rc != 0 && sync_err != EINVAL && sync_err != ENOTSUP)
    throw InputError(path + ": written, but its folder could not be synced (" +
                     std::strerror(sync_err) + "): the file may not survive a crash");
}

std::string read_file_bytes(const std::string& path, uint64_t max_bytes) {
  // Open first, then look at what was opened (no race between a check and the read).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block
  if (fd < 0) throw InputError(path + ": cannot open for reading (" + std::strerror(errno) + ")");
  struct stat st {};
  std::string what;
  if (::fstat(fd, &st) != 0)
    what = std::string("cannot read its status (") + std::strerror(errno) + ")";
  else if (S_ISDIR(st.st_mode))
    what = "is a directory, not a file";
  else if (!S_ISREG(st.st_mode))
    what = "is not a regular file (a device, pipe or socket)";
  else if (static_cast<uint64_t>(st.st_size) > max_bytes)
    what = "is " + std::to_string(st.st_size) + " bytes, more than the limit of " +
           std::to_string(max_bytes) + " bytes for this kind of file";
  std::string bytes;
  if (what.empty()) {
    bytes.resize(static_cast<size_t>(st.st_size));
    size_t got = 0;
    while (got < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        what = std::string("read failed (") + std::strerror(errno) + ")";
        break;
      }
      if (n == 0) break;  // shrank while reading: take what is there
      got += static_cast<size_t>(n);
    }
    bytes.resize(got);
  }
  ::close(fd);
  if (!what.empty()) throw InputError(path + ": " + what);
  return bytes;
}

}  // namespace plastivox
