// Fault injection for tests, loaded with LD_PRELOAD: while PLASTIVOX_TEST_FAIL_FOLDER_SYNC is
// set, fsync() of a folder fails with EIO, as a failing disk would report it after a rename.
// Every other fsync() is the C library's.
#include <dlfcn.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdlib>

extern "C" int fsync(int fd) {
  using Fsync = int (*)(int);
  static const Fsync real = reinterpret_cast<Fsync>(dlsym(RTLD_NEXT, "fsync"));
  struct stat st {};
  if (std::getenv("PLASTIVOX_TEST_FAIL_FOLDER_SYNC") && fstat(fd, &st) == 0 &&
      S_ISDIR(st.st_mode)) {
    errno = EIO;
    return -1;
  }
  return real(fd);
}
