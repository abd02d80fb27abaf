// Progress display: terminal status line or plain lines.
#include "progress.hpp"

#include <unistd.h>

#include <chrono>
#include <ctime>

namespace plastivox::experiment {
namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Progress::Progress(std::FILE* out) : out_(out), tty_(isatty(fileno(out)) == 1) {}

Progress::~Progress() {
  clear_status();
}

void Progress::set_log_file(const std::string& path) {
  log_.open(path, std::ios::app);  // a log that cannot be opened is not fatal
}

void Progress::clear_status() {
  if (tty_ && status_shown_) {
    std::fputs("\r\033[K", out_);
    std::fflush(out_);
    status_shown_ = false;
  }
}

void Progress::log(const std::string& line) {
  clear_status();
  std::fprintf(out_, "%s\n", line.c_str());
  std::fflush(out_);
  if (log_) log_ << utc_timestamp() << " " << line << "\n" << std::flush;
}

void Progress::status(const std::string& line) {
  if (tty_) {
    std::fprintf(out_, "\r\033[K%s", line.c_str());
    std::fflush(out_);
    status_shown_ = true;
    return;
  }
  const double t = now_seconds();
  if (t - last_plain_ < plain_interval) return;
  last_plain_ = t;
  std::fprintf(out_, "%s\n", line.c_str());
  std::fflush(out_);
}

}  // namespace plastivox::experiment
