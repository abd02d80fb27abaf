// Text in HTML and SVG output (the study report, the figure panels): one escaper.
#pragma once

#include <string>

namespace plastivox {

// `text` with & < > " as entities, and ' as &#39; when `apostrophe` is set.
inline std::string escape_markup(const std::string& text, bool apostrophe) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += apostrophe ? "&#39;" : "'";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

}  // namespace plastivox
