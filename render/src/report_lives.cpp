// The lives beside a report (plastivox/render/viewer.hpp): one script per life in
// <report>/lives/, written atomically, and the scripts of lives no longer shown removed.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/viewer.hpp"

namespace plastivox::render {

ViewerLink write_report_life(const std::string& dir, const std::string& id,
                             const ViewerItem& life) {
  std::filesystem::create_directories(dir + "/lives");
  write_file_atomic(dir + "/lives/" + id + ".js", life_script(id, life));
  return ViewerLink{id, "lives/" + id + ".js"};
}

void remove_other_lives(const std::string& dir, const std::vector<ViewerLink>& keep) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir + "/lives")) return;
  for (const auto& e : fs::directory_iterator(dir + "/lives")) {
    const std::string src = "lives/" + e.path().filename().string();
    const bool kept =
        std::any_of(keep.begin(), keep.end(), [&](const ViewerLink& l) { return l.src == src; });
    if (!kept && e.path().extension() == ".js") fs::remove(e.path());
  }
}

}  // namespace plastivox::render
