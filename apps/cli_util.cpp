#include "cli.hpp"

#include <algorithm>

namespace plastivox::cli {

std::string take_option(Args& args, const std::string& name, const std::string& fallback) {
  auto it = std::find(args.begin(), args.end(), name);
  if (it == args.end()) return fallback;
  if (it + 1 == args.end()) throw UsageError{"option " + name + " needs a value"};
  std::string value = *(it + 1);
  args.erase(it, it + 2);
  return value;
}

bool take_flag(Args& args, const std::string& name) {
  auto it = std::find(args.begin(), args.end(), name);
  if (it == args.end()) return false;
  args.erase(it);
  return true;
}

void reject_unknown_options(const Args& args) {
  for (const std::string& a : args)
    if (a.size() > 1 && a[0] == '-') throw UsageError{"unknown option " + a};
}

}  // namespace plastivox::cli
