// Writing a study's output folder: every file first under "<name>.tmp", then renamed, with
// stats.json last, so its presence means every other output of that analysis is complete.
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "study_internal.hpp"

namespace plastivox::analysis {

void write_study_outputs(const StudyResult& r, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error(dir + ": cannot create the output folder (" + ec.message() + ")");
  auto in_dir = [&](const char* name) { return (fs::path(dir) / name).string(); };

  const std::vector<std::pair<std::string, std::string>> texts = {
      {in_dir("champions.csv"), champions_csv(r)},
      {in_dir("statistics.csv"), statistics_csv(r)},
      {in_dir("hausdorff.csv"), hausdorff_csv(r)},
      {in_dir("stats.json"), stats_json(r)},
  };
  const std::string h5 = in_dir("analysis.h5");
  try {
    for (const auto& [path, text] : texts) study::write_temp(path, text);
    study::write_analysis_h5(r, h5, h5 + ".tmp");
    study::sync_file(h5 + ".tmp", h5);
  } catch (...) {  // any failure: no temporary is left behind, and the error goes on as it was
    for (const auto& [path, text] : texts) std::remove((path + ".tmp").c_str());
    std::remove((h5 + ".tmp").c_str());
    throw;
  }
  study::commit_temp(h5);
  for (const auto& [path, text] : texts) study::commit_temp(path);  // stats.json last
}

void write_study_report(const StudyResult& r, const std::string& path, const ReportExtras& extras) {
  study::write_atomically(path, report_html(r, extras));
}

}  // namespace plastivox::analysis
