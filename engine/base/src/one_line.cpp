#include "plastivox/base/one_line.hpp"

namespace plastivox {

std::string one_line(std::string s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const auto next = i + 1 < s.size() ? static_cast<unsigned char>(s[i + 1]) : 0u;
    const auto after = i + 2 < s.size() ? static_cast<unsigned char>(s[i + 2]) : 0u;
    if (c < 0x20 || c == 0x7f) {
      out += ' ';
    } else if (c == 0xc2 && next == 0x85) {  // NEL
      out += ' ';
      i += 1;
    } else if (c == 0xe2 && next == 0x80 && (after == 0xa8 || after == 0xa9)) {  // LS, PS
      out += ' ';
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace plastivox
