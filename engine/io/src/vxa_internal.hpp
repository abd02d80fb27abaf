// Helpers shared by the VXA reader and writer (they must agree bit for bit on how a number is
// printed and parsed and on how actuation is derived from the thermal tags, or a round trip
// would not be exact), then the XML writer and the reader's XML helpers (tag paths, one-line
// errors), which the voxcraft-sim dialect (voxcraft_*.cpp) uses too.
#pragma once

#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "plastivox/base/one_line.hpp"
#include "plastivox/io/vxa.hpp"

namespace plastivox::vxa_detail {

// What the authors' files use: every voxel is palette material 3, TempBase 25, CTE 0.01.
constexpr int kActiveMaterial = 3;
constexpr double kTempBase = 25.0;
constexpr double kCte = 0.01;
// Voxelyze 0.9's hard-coded MIN_TEMP_FACTOR.
constexpr double kMinTempFactor = 0.1;
// The authors' CollisionHorizon: self-collision ignores voxels within (int)(1.5 * H) bonds.
constexpr double kCollisionHorizon = 2.0;

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Locale-independent; accepts surrounding whitespace and a leading '+'; rejects anything else
// that is not a complete finite number.
inline bool parse_double(std::string_view s, double* out) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// Shortest text that parses back to exactly v (std::to_chars is locale-independent).
inline std::string format_double(double v) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("0");
}

// Linear actuation amplitude from the thermal tags (TempAmplitude is the modern tag; the
// legacy TempAmp is converted to TempAmp - TempBase as the authors' environment reader does).
inline double amplitude_from_temp_amp(double temp_amp, double temp_base, double cte) {
  return (temp_amp - temp_base) * cte;
}

inline double frequency_from_period(double period) {
  return 1.0 / period;
}

// ---- XML writing (vxa_write.cpp, voxcraft_write.cpp) ----

// Unindented XML text built tag by tag; text is written as given (callers pass numbers and
// names without markup characters, or CDATA layers).
class Xml {
 public:
  explicit Xml(size_t reserve) { s_.reserve(reserve); }
  void open(const std::string& tag, const std::string& attrs = "") {
    s_ += "<" + tag + attrs + ">\n";
    stack_.push_back(tag);
  }
  void close() {
    s_ += "</" + stack_.back() + ">\n";
    stack_.pop_back();
  }
  void tag(const std::string& name, const std::string& text) {
    s_ += "<" + name + ">" + text + "</" + name + ">\n";
  }
  void tag(const std::string& name, double v) { tag(name, format_double(v)); }
  // An element holding one number: <name><inner>v</inner></name>.
  void block(const std::string& name, const std::string& inner, double v) {
    open(name);
    tag(inner, v);
    close();
  }
  void layer(const std::string& text) { s_ += "<Layer><![CDATA[" + text + "]]></Layer>\n"; }
  std::string& text() { return s_; }

 private:
  std::string s_;
  std::vector<std::string> stack_;
};

// <Damping>, as both dialects read it: the three damping ratios.
inline void write_damping(Xml& x, const PhysicsDef& p) {
  x.open("Damping");
  x.tag("BondDampingZ", p.bond_damping);
  x.tag("ColDampingZ", p.collision_damping);
  x.tag("SlowDampingZ", p.global_damping);
  x.close();
}

// ---- XML reading helpers (vxa_read.cpp) ----

using tinyxml2::XMLElement;

using plastivox::one_line;

inline std::string quoted(std::string_view s) {
  s = trim(s);
  std::string out(1, '\'');
  out.append(s.substr(0, 40));
  out.append(s.size() > 40 ? "...'" : "'");
  return out;
}

// "<VXC>/<Palette>/<Material ID="3">/<Mechanical>": the element's path below the root <VXA>.
inline std::string tag_path(const XMLElement* e) {
  std::string path;
  for (; e && e->Parent() && e->Parent()->ToElement(); e = e->Parent()->ToElement()) {
    std::string tag = std::string("<") + e->Name();
    if (const char* id = e->Attribute("ID")) tag += std::string(" ID=\"") + id + "\"";
    path = tag + ">" + (path.empty() ? "" : "/" + path);
  }
  return path.empty() ? "<VXA>" : path;
}

// Best-effort context for a parse error: the elements still open when the scan of the text
// reaches the end of line stop_line (or the end of a truncated text), e.g. "<VXA>/<VXC>".
inline std::string open_elements(std::string_view text, int stop_line) {
  std::vector<std::string> stack;
  int line = 1;
  size_t i = 0;
  auto skip_past = [&](std::string_view end) {
    const size_t j = text.find(end, i);
    const size_t stop = j == std::string_view::npos ? text.size() : j + end.size();
    line += static_cast<int>(std::count(text.begin() + i, text.begin() + stop, '\n'));
    i = stop;
    return j != std::string_view::npos;
  };
  while (i < text.size() && line <= stop_line) {
    const std::string_view rest = text.substr(i);
    if (rest[0] != '<') {
      line += rest[0] == '\n';
      ++i;
    } else if (rest.starts_with("<!--")) {
      skip_past("-->");
    } else if (rest.starts_with("<![CDATA[")) {
      skip_past("]]>");
    } else if (rest.starts_with("<?") || rest.starts_with("<!")) {
      skip_past(">");
    } else {
      const bool closing = rest.starts_with("</");
      size_t end = closing ? 2 : 1;
      while (end < rest.size() && !is_space(rest[end]) && rest[end] != '>' && rest[end] != '/')
        ++end;
      const std::string name(rest.substr(closing ? 2 : 1, end - (closing ? 2 : 1)));
      if (!skip_past(">")) {  // the text ends inside this tag
        if (!closing) stack.push_back(name);
        break;
      }
      if (closing) {
        if (!stack.empty() && stack.back() == name) stack.pop_back();
      } else if (text[i - 2] != '/' && !name.empty()) {
        stack.push_back(name);
      }
    }
  }
  std::string path;
  for (const std::string& name : stack) path += (path.empty() ? "<" : "/<") + name + ">";
  return path.empty() ? "(document)" : path;
}

// Parses text into doc. Throws VxaError, one line naming the file, for malformed XML (with the
// elements open at the error) or an element with more than kMaxVxaAttributes attributes.
void parse_xml_document(tinyxml2::XMLDocument& doc, const std::string& text,
                        const std::string& source_name);

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}
  std::vector<std::string> warnings;

  [[noreturn]] void fail(const XMLElement* at, const std::string& what) const {
    throw VxaError(one_line(source_ + ": " + tag_path(at) + ": " + what));
  }
  void warn(const XMLElement* at, const std::string& what) {
    warnings.push_back(one_line(source_ + ": " + tag_path(at) + ": " + what));
  }
  static const XMLElement* child(const XMLElement* parent, const char* name) {
    return parent ? parent->FirstChildElement(name) : nullptr;
  }
  const XMLElement* need(const XMLElement* parent, const char* name) const {
    const XMLElement* e = child(parent, name);
    if (!e) fail(parent, std::string("missing <") + name + ">");
    return e;
  }
  // A section the authors' simulator treats as optional: absent means its built-in defaults.
  const XMLElement* section(const XMLElement* parent, const char* name) {
    const XMLElement* e = child(parent, name);
    if (!e) warn(parent, std::string("no <") + name + ">: using the authors' simulator defaults");
    return e;
  }
  double number(const XMLElement* e) const {
    const char* text = e->GetText();
    double v = 0;
    if (!text || !parse_double(text, &v)) fail(e, quoted(text ? text : "") + " is not a number");
    return v;
  }
  // The tag's value; if the tag is absent, def (the authors' default for it) and a warning.
  double opt(const XMLElement* parent, const char* name, double def) {
    if (const XMLElement* e = child(parent, name)) return number(e);
    if (parent) warn(parent, std::string("no <") + name + ">: using " + format_double(def));
    return def;
  }
  double required(const XMLElement* parent, const char* name) const {
    return number(need(parent, name));
  }
  bool flag(const XMLElement* parent, const char* name, bool def) {
    const XMLElement* e = child(parent, name);
    const double v = e ? number(e) : opt(parent, name, def ? 1 : 0);
    if (v != 0 && v != 1) fail(e, format_double(v) + " is not 0 or 1");
    return v != 0;
  }
  int whole(const XMLElement* e, double v, int lo, int hi) const {
    if (v != std::floor(v) || v < lo || v > hi)
      fail(e, format_double(v) + " is not a whole number in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  // A tag this engine cannot honour unless it has its neutral value (absent counts as neutral).
  void expect(const XMLElement* parent, const char* name, double neutral, bool error,
              const std::string& why) {
    const XMLElement* e = child(parent, name);
    if (!e) return;
    const double v = number(e);
    if (v == neutral) return;
    const std::string msg =
        format_double(v) + " is not supported (only " + format_double(neutral) + "): " + why;
    if (error) fail(e, msg);
    warn(e, msg + "; ignored");
  }

  std::vector<const XMLElement*> layers(const XMLElement* block, int nz) const {
    std::vector<const XMLElement*> out;
    for (const XMLElement* l = block->FirstChildElement("Layer"); l;
         l = l->NextSiblingElement("Layer"))
      out.push_back(l);
    if (static_cast<int>(out.size()) != nz)
      fail(block, "has " + std::to_string(out.size()) + " <Layer> elements, expected " +
                      std::to_string(nz) + " (Z_Voxels)");
    return out;
  }

  // One comma-separated value per lattice site, layer by layer (a trailing comma is allowed).
  std::vector<double> site_values(const XMLElement* block, int nx, int ny, int nz) const {
    const auto ls = layers(block, nz);
    const size_t per_layer = static_cast<size_t>(nx) * ny;
    std::vector<double> out;
    out.reserve(per_layer * nz);
    for (int z = 0; z < nz; ++z) {
      const std::string where = "layer " + std::to_string(z + 1) + " of " + std::to_string(nz);
      const char* raw = ls[z]->GetText();
      std::string_view text = raw ? raw : "";
      size_t count = 0;
      while (true) {
        const size_t comma = text.find(',');
        const std::string_view token = text.substr(0, comma);
        const bool last = comma == std::string_view::npos;
        if (last && trim(token).empty() && count > 0) break;  // trailing comma
        double v = 0;
        if (!parse_double(token, &v))
          fail(ls[z], where + ": value " + std::to_string(count + 1) + " " + quoted(token) +
                          " is not a number");
        out.push_back(v);
        ++count;
        if (last) break;
        text.remove_prefix(comma + 1);
      }
      if (count != per_layer)
        fail(ls[z], where + " has " + std::to_string(count) + " values, expected " +
                        std::to_string(per_layer) + " (X_Voxels*Y_Voxels)");
    }
    return out;
  }

 private:
  std::string source_;
};

}  // namespace plastivox::vxa_detail
