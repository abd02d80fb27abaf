// The plastivox command line: one function per subcommand, shared argument helpers.
#pragma once

#include <string>
#include <vector>

namespace plastivox::cli {

using Args = std::vector<std::string>;

// Thrown for a malformed command line; main prints the message and exits with status 2.
struct UsageError {
  std::string message;
};

int cmd_simulate(const Args& args);
int cmd_demo(const Args& args);
int cmd_evolve(const Args& args);     // apps/cmd_evolve.cpp
int cmd_inspect(const Args& args);    // apps/cmd_inspect.cpp
int cmd_hausdorff(const Args& args);  // apps/cmd_hausdorff.cpp
int cmd_export(const Args& args);     // apps/cmd_export.cpp

// Removes "--name VALUE" from args and returns VALUE (or fallback when absent).
std::string take_option(Args& args, const std::string& name, const std::string& fallback);
// Removes "--name" from args and returns whether it was there.
bool take_flag(Args& args, const std::string& name);
// After options are taken: error on any leftover "--something".
void reject_unknown_options(const Args& args);

}  // namespace plastivox::cli
