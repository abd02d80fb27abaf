// The usage lines of README.md ("Using it") and examples/README.md ("Try them") run as
// written, in order, as a user would from a fresh clone: examples/ beside them, plastivox on
// the PATH. Slow (a small evolution, a small experiment, a video): labelled "slow".
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace plastivox {
namespace {

namespace fs = std::filesystem;

const std::string kExamples = std::string(PLASTIVOX_SOURCE_DIR) + "/examples";

// The command lines of the first ```sh block after `heading` in a Markdown file (comments
// after '#' dropped, blank lines skipped).
std::vector<std::string> usage_lines(const std::string& markdown, const std::string& heading) {
  const std::string text = testing::file_text(markdown);
  size_t at = text.find(heading);
  EXPECT_NE(at, std::string::npos) << markdown << " has no '" << heading << "'";
  at = text.find("```sh\n", at);
  EXPECT_NE(at, std::string::npos) << markdown << ": no ```sh block after " << heading;
  const size_t end = text.find("```", at + 6);
  std::istringstream block(text.substr(at + 6, end - at - 6));
  std::vector<std::string> lines;
  for (std::string line; std::getline(block, line);) {
    // A '#' starts a comment unless it is inside quotes (none of our lines quote one).
    const size_t hash = line.find(" #");
    if (hash != std::string::npos) line = line.substr(0, hash);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

class Usage : public testing::ScratchDirTest {
 protected:
  // Runs each line with sh in the scratch folder, as a user in a fresh clone would:
  // examples/ beside it, plastivox on the PATH.
  void run_lines(const std::vector<std::string>& lines) {
    fs::create_directory_symlink(kExamples, dir_ / "examples");
    const std::string bin = fs::path(PLASTIVOX_CLI).parent_path().string();
    for (const std::string& line : lines) {
      SCOPED_TRACE(line);
      const testing::Output r = testing::shell("cd '" + dir_.string() + "' && PATH='" + bin +
                                               "':\"$PATH\" " + line + " 2>&1");
      EXPECT_EQ(r.status, 0) << r.out;
    }
  }
};

TEST_F(Usage, ExamplesReadmeUsageLinesRunAsWritten) {
  const auto lines = usage_lines(kExamples + "/README.md", "## Try them");
  EXPECT_GE(lines.size(), 5u);
  run_lines(lines);
}

TEST_F(Usage, ReadmeUsageLinesRunAsWritten) {
  const auto lines = usage_lines(std::string(PLASTIVOX_SOURCE_DIR) + "/README.md", "## Using it");
  EXPECT_GE(lines.size(), 15u);
  run_lines(lines);
  for (const char* out : {"run.h5", "champion.vxa", "frame.png", "life.mp4", "stress.png",
                          "figures/panel_A.png", "analysis/stats.json"})
    EXPECT_TRUE(fs::exists(dir_ / out)) << out;
}

}  // namespace
}  // namespace plastivox
