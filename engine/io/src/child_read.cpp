#include "plastivox/io/child_read.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>

namespace plastivox {
namespace {

constexpr int kThrew = 3;             // the child's exit status when `read` threw
constexpr size_t kMaxMessage = 4096;  // an error is one line; more is not read

void write_all(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<size_t>(n);
  }
}

[[noreturn]] void child(int out, const std::function<void()>& read, int cpu_seconds) {
  // A crash is what this process is for: no core file, and nothing on the terminal (HDF5 or
  // a sanitizer may print before dying; the parent says what happened in one line). A read
  // that loops is ended by the kernel (SIGXCPU) after `cpu_seconds`.
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  const rlim_t cpu = static_cast<rlim_t>(std::max(cpu_seconds, 1));
  const rlimit cpu_limit{cpu, cpu + 1};  // SIGXCPU at the soft limit, SIGKILL a second later
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
  // A read that blocks uses no CPU: a fork copies a lock another thread held (HDF5's global
  // one, say) and the child would wait for ever. SIGALRM ends it after ample wall time.
  ::alarm(static_cast<unsigned>(10 * cpu + 10));
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) ::dup2(null, STDERR_FILENO);
  int status = 0;
  try {
    read();
  } catch (const std::exception& e) {
    write_all(out, std::string(e.what()).substr(0, kMaxMessage));
    status = kThrew;
  } catch (...) {
    write_all(out, "an unknown error");
    status = kThrew;
  }
  ::_exit(status);  // no atexit handlers, no flushing of the parent's buffered output
}

}  // namespace

ChildRead run_in_child(const std::function<void()>& read, int cpu_seconds) {
  ChildRead r;
  int fds[2];
  if (::pipe(fds) != 0) {
    r.outcome = ChildRead::Outcome::kNoChild;
    r.message = std::string("cannot make a pipe: ") + std::strerror(errno);
    return r;
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    r.outcome = ChildRead::Outcome::kNoChild;
    r.message = std::string("cannot start a process: ") + std::strerror(e);
    return r;
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], read, cpu_seconds);
  }
  ::close(fds[1]);
  std::string text;
  char buf[512];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (text.size() < kMaxMessage) text.append(buf, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      r.outcome = ChildRead::Outcome::kNoChild;
      r.message = std::string("cannot wait for the reading process: ") + std::strerror(errno);
      return r;
    }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return r;
  if (WIFEXITED(status) && WEXITSTATUS(status) == kThrew && !text.empty()) {
    r.outcome = ChildRead::Outcome::kError;
    r.message = text;
    return r;
  }
  r.outcome = ChildRead::Outcome::kCrashed;
  if (WIFSIGNALED(status))
    r.message =
        "signal " + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
  else  // a sanitizer's report ends the process with a status instead of the signal
    r.message = "exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  return r;
}

}  // namespace plastivox
