// The 3-D viewer's page (plastivox/render/viewer.hpp). The page is plain HTML with three
// scripts inlined: three.js and its OrbitControls from Debian's libjs-three, and the viewer
// (assets/viewer/viewer.js). Each life travels as base64 of its packed bytes plus a small
// JSON of what to read out and how to colour, so one page holds everything it needs.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "plastivox/base/error.hpp"      // InputError
#include "plastivox/io/atomic_file.hpp"  // read_file_bytes
#include "plastivox/render/assets.hpp"
#include "plastivox/render/colormap.hpp"
#include "plastivox/render/error.hpp"
#include "plastivox/render/viewer.hpp"

namespace plastivox::render {
namespace {

constexpr const char* kThreeDir = "/usr/share/javascript/three";

std::string read_text(const std::string& path, const std::string& what) {
  try {
    return read_file_bytes(path);
  } catch (const InputError&) {
    throw RenderError(path + ": missing (" + what + ")");
  }
}

// Text safe inside <script>...</script>: no "</script" can close the element early (in
// JavaScript, "<\/script" inside a string or comment means the same).
std::string script_safe(std::string s) {
  for (size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 2) {
    std::string word = s.substr(at + 2, 6);
    std::transform(word.begin(), word.end(), word.begin(), [](char c) { return std::tolower(c); });
    if (word == "script") s.replace(at, 2, "<\\/");
  }
  return s;
}

// The renderer's colour maps as the viewer reads them: name -> flat RGB bytes.
std::string colormaps_json() {
  nlohmann::json maps;
  const std::pair<const char*, const Colormap*> all[] = {{"sequential", &Colormap::sequential()},
                                                         {"diverging", &Colormap::diverging()},
                                                         {"cyclic", &Colormap::cyclic_map()}};
  for (const auto& [name, map] : all) {
    std::vector<int> rgb;
    for (int k = 0; k < Colormap::kEntries; ++k)
      for (uint8_t c : map->at(k / static_cast<double>(Colormap::kEntries - 1))) rgb.push_back(c);
    maps[name] = rgb;
  }
  return maps.dump();
}

// three.js, its OrbitControls, the colour maps and the viewer, inlined; `lives_js` (already
// script-safe) fills PLASTIVOX_LIVES before the viewer's script runs.
std::string scripts_html(const std::string& lives_js) {
  const ViewerScripts js = viewer_scripts();
  std::string html;
  html += "<script>" + script_safe(js.three) + "</script>\n";
  html += "<script>" + script_safe(js.orbit) + "</script>\n";
  html += "<script>window.PLASTIVOX_COLORMAPS = " + colormaps_json() +
          ";\nwindow.PLASTIVOX_LIVES = [];\n" + lives_js + "</script>\n";
  html += "<script>" + script_safe(js.viewer) + "</script>\n";
  return html;
}

// A button per life (labels set by the script from each life's meta).
std::string buttons_html(size_t n) {
  std::string html = "<div class=\"pv-lives\">";
  for (size_t i = 0; i < n; ++i)
    html += "<button type=\"button\" data-pv-life=\"" + std::to_string(i) +
            "\" onclick=\"plastivoxViewer.load(" + std::to_string(i) + ")\"></button>";
  return html + "</div>\n";
}

// One life as the viewer reads it: {meta: <life_meta_json>, data: "<base64 of pack_life>"}.
std::string life_object_js(const ViewerItem& life) {
  return "{meta: " + life_meta_json(life) + ", data: \"" + base64(pack_life(life)) + "\"}";
}

const char* kStart =
    "<script>plastivoxViewer.start(document.getElementById(\"pv-viewer\"), 0);</script>\n";

}  // namespace

ViewerScripts viewer_scripts() {
  const std::string hint = "Debian package libjs-three: apt-get install -y libjs-three";
  ViewerScripts s;
  s.three = read_text(std::string(kThreeDir) + "/three.min.js", hint);
  s.orbit = read_text(std::string(kThreeDir) + "/examples/js/controls/OrbitControls.js", hint);
  s.viewer = read_asset("viewer/viewer.js");
  return s;
}

std::string viewer_page(const std::vector<ViewerItem>& lives, const std::string& title) {
  // Text from files (robot names, labels) reaches the page only as JSON, set by the script
  // as text: nothing in it is parsed as HTML.
  std::string html;
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html +=
      "<title>plastivox viewer</title>\n<meta name=\"viewport\" content=\"width=device-width\">\n";
  html += "<style>body { font-family: sans-serif; margin: 1em; color: #222; }</style>\n";
  html += read_asset("viewer/viewer.css.html");
  html += "</head>\n<body>\n<h1 class=\"pv-title\"></h1>\n";
  if (lives.size() > 1) html += buttons_html(lives.size());  // one viewer; these pick its life
  html += read_asset("viewer/viewer_panel.html");
  std::string list;
  for (const ViewerItem& life : lives)
    list += "PLASTIVOX_LIVES.push(" + script_safe(life_object_js(life)) + ");\n";
  html += scripts_html(list);
  html += "<script>document.title = document.querySelector(\".pv-title\").textContent = " +
          script_safe(nlohmann::json(title).dump()) + ";</script>\n";
  html += kStart;
  html += "</body>\n</html>\n";
  return html;
}

std::string life_script(const std::string& id, const ViewerItem& life) {
  return "plastivoxViewer.deliver(" + nlohmann::json(id).dump() + ", " + life_object_js(life) +
         ");\n";
}

std::string viewer_fragment(const std::vector<ViewerLink>& lives, bool buttons) {
  if (lives.empty()) return "";
  std::string html = read_asset("viewer/viewer.css.html");
  if (buttons) html += buttons_html(lives.size());
  html += read_asset("viewer/viewer_panel.html");
  std::string list;
  for (const ViewerLink& l : lives)
    list += "PLASTIVOX_LIVES.push({id: " + nlohmann::json(l.id).dump() +
            ", src: " + nlohmann::json(l.src).dump() +
            ", meta: {label: " + nlohmann::json(l.id).dump() + "}});\n";
  html += scripts_html(script_safe(list));
  html += kStart;
  return html;
}

}  // namespace plastivox::render
