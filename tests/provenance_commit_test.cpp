// The commit in every result file's provenance is the one the sources were at when the binary
// was built (cmake/commit_stamp.cmake, run at every build), with "-dirty" when tracked files
// differed from it. Until 2026-12-07 it was taken when CMake configured the build folder, so a
// pull and a rebuild kept stamping results with the older commit.
#include <chrono>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "plastivox/io/provenance.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

std::string first_line(const std::string& s) {
  return s.substr(0, s.find('\n'));
}

// Runs a command away from any repository the test itself runs inside (a git hook's GIT_DIR).
constexpr const char* kOwnGit = "env -u GIT_DIR -u GIT_WORK_TREE -u GIT_INDEX_FILE ";

class CommitStamp : public testing::ScratchDirTest {
 protected:
  // Runs the stamp script on `source`; the header it wrote.
  std::string stamp(const std::string& source) const {
    const testing::Output o = testing::shell(
        std::string(kOwnGit) + "'" + PLASTIVOX_CMAKE + "' -DSOURCE_DIR='" + source + "' -DOUT='" +
        path("commit.hpp") + "' -P '" + PLASTIVOX_SOURCE_DIR + "/cmake/commit_stamp.cmake' 2>&1");
    EXPECT_EQ(o.status, 0) << o.out;
    return testing::file_text(path("commit.hpp"));
  }
  // git in the scratch repository, away from this machine's git settings.
  std::string git(const std::string& args) const {
    const testing::Output o = testing::shell(
        "cd '" + path("src") + "' && " + kOwnGit +
        "GIT_CONFIG_NOSYSTEM=1 GIT_CONFIG_GLOBAL=/dev/null git -c user.name=t -c user.email=t@t -c "
        "commit.gpgsign=false " +
        args + " 2>&1");
    EXPECT_EQ(o.status, 0) << args << ": " << o.out;
    return first_line(o.out);
  }
};

TEST_F(CommitStamp, TakesTheCommitAndWhetherTrackedFilesDiffer) {
  std::filesystem::create_directory(path("src"));
  // Not a git work tree (a copy of the sources, as pip's build makes): unknown.
  EXPECT_NE(stamp(path("src")).find("#define PLASTIVOX_BUILD_GIT_COMMIT \"unknown\""),
            std::string::npos);
  git("init -q");
  write("src/a.txt", "one\n");
  git("add a.txt");
  git("commit -q -m one");
  const std::string one = git("rev-parse --short=12 HEAD");
  ASSERT_EQ(one.size(), 12u);
  EXPECT_NE(stamp(path("src")).find("\"" + one + "\""), std::string::npos);
  // An untracked file is not a change; an edit of a tracked one is.
  write("src/b.txt", "new\n");
  EXPECT_NE(stamp(path("src")).find("\"" + one + "\""), std::string::npos);
  write("src/a.txt", "two\n");
  EXPECT_NE(stamp(path("src")).find("\"" + one + "-dirty\""), std::string::npos);
  // Committed: the new commit, clean. The header is rewritten only when that changes.
  git("commit -q -am two");
  const std::string two = git("rev-parse --short=12 HEAD");
  EXPECT_NE(two, one);
  EXPECT_NE(stamp(path("src")).find("\"" + two + "\""), std::string::npos);
  const std::string header = path("commit.hpp");
  std::filesystem::last_write_time(
      header, std::filesystem::last_write_time(header) - std::chrono::hours(1));
  const auto set = std::filesystem::last_write_time(header);  // as the file system keeps it
  stamp(path("src"));
  EXPECT_EQ(std::filesystem::last_write_time(header), set)
      << "rewritten without a change: every build would recompile build_commit.cpp";
  // A copy of the sources inside another repository is not that repository's commit.
  std::filesystem::create_directory(path("src/copy"));
  EXPECT_NE(stamp(path("src/copy")).find("\"unknown\""), std::string::npos);
}

// This build's own stamp, in every result file's provenance and in `plastivox --version`: a
// commit of the sources' history (HEAD, or one before it when a commit came after the build;
// "-dirty" when tracked files had been edited then), or "unknown" when the sources are not the
// top of a git work tree.
TEST(Provenance, CommitIsFromTheSourcesHistory) {
  const std::string source = std::filesystem::canonical(PLASTIVOX_SOURCE_DIR).string();
  const testing::Output top =
      testing::shell("git -C '" + source + "' rev-parse --show-toplevel 2>/dev/null");
  const bool repository = top.status == 0 && first_line(top.out) == source;
  const auto check = [&](const std::string& stamp, const char* whose) {
    SCOPED_TRACE(whose);
    if (!repository) {
      EXPECT_EQ(stamp, "unknown");
      return;
    }
    const std::string commit = stamp.substr(0, stamp.find("-dirty"));
    EXPECT_EQ(commit.size(), 12u) << stamp;
    const testing::Output ancestor = testing::shell(
        "git -C '" + source + "' merge-base --is-ancestor '" + commit + "' HEAD 2>&1");
    EXPECT_EQ(ancestor.status, 0) << "built at " << stamp
                                  << ", not a commit of the sources' history: " << ancestor.out;
  };
  const std::string built = build_git_commit();
  EXPECT_EQ(current_provenance(1).git_commit, built);
  check(built, "the library");
  // The program (a separate link: built with the library, unless only this test was rebuilt).
  const testing::Output version = testing::cli("--version");
  ASSERT_EQ(version.status, 0);
  const size_t at = version.out.find("(commit ");
  ASSERT_NE(at, std::string::npos) << version.out;
  const size_t from = at + 8;
  check(version.out.substr(from, version.out.find(')', from) - from), "plastivox --version");
}

}  // namespace
}  // namespace plastivox
