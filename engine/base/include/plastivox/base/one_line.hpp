// Error messages are one line, whatever they quote (a damaged tag name, a path).
#pragma once

#include <string>

namespace plastivox {

// s with everything that could break a line replaced by a space: control characters (\n,
// \r, \v, \f, ...), NEL (U+0085) and the Unicode line and paragraph separators.
std::string one_line(std::string s);

}  // namespace plastivox
