// Progress for long work: one self-updating status line on a terminal, plain log lines
// otherwise (CI logs, files, pipes). Every permanent line also goes to an optional log file.
#pragma once

#include <cstdio>
#include <fstream>
#include <string>

#include "plastivox/base/clock.hpp"  // utc_timestamp: log lines and the folder manifest

namespace plastivox::experiment {

class Progress {
 public:
  explicit Progress(std::FILE* out);  // a terminal is detected with isatty()
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void set_log_file(const std::string& path);  // appended to
  // A permanent line: "[evolve] stress-s2: resuming after generation 12".
  void log(const std::string& line);
  // The transient status ("evolve 3/6 stress-s1 gen 12/30 | ETA 4 min"): rewritten in place
  // on a terminal; elsewhere printed as a line at most every `plain_interval` seconds.
  void status(const std::string& line);
  bool is_terminal() const { return tty_; }
  double plain_interval = 10;

 private:
  void clear_status();
  std::FILE* out_;
  bool tty_ = false;
  bool status_shown_ = false;
  double last_plain_ = -1e300;
  std::ofstream log_;
};

}  // namespace plastivox::experiment
