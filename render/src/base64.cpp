// Standard base64 (RFC 4648, with padding): how a packed life travels inside a page or a
// script (plastivox/render/viewer.hpp).
#include <cstdint>
#include <string>

#include "plastivox/render/viewer.hpp"

namespace plastivox::render {

std::string base64(const std::string& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t left = bytes.size() - i;
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (left > 1) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (left > 2) v |= static_cast<uint8_t>(bytes[i + 2]);
    out.push_back(abc[(v >> 18) & 63]);
    out.push_back(abc[(v >> 12) & 63]);
    out.push_back(left > 1 ? abc[(v >> 6) & 63] : '=');
    out.push_back(left > 2 ? abc[v & 63] : '=');
  }
  return out;
}

}  // namespace plastivox::render
