// One number printed with a printf format, as a string (labels, ticks, captions).
#pragma once

#include <cstdio>
#include <string>

namespace plastivox::render {

inline std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace plastivox::render
