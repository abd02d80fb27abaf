// examples/: the robots are exactly what `plastivox export --demo` writes, the body-plan
// examples are classified as their names say, the walker file is the built-in walker.
// (readme_usage_test runs the README's usage lines.)
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/io/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

const std::string kExamples = std::string(PLASTIVOX_SOURCE_DIR) + "/examples";

class Examples : public testing::ScratchDirTest {};

TEST_F(Examples, RobotFilesAreWhatExportDemoWrites) {
  for (const char* name : {"walker", "pi", "gamma", "upsilon", "mixture"})
    for (const char* ext : {".json", ".vxa"}) {
      SCOPED_TRACE(std::string(name) + ext);
      const std::string out = path(std::string(name) + ext);
      const testing::Output r = cli("export --demo " + std::string(name) + " --out " + out);
      ASSERT_EQ(r.status, 0) << r.out;
      const std::string shipped = testing::file_text(kExamples + "/" + name + ext);
      ASSERT_FALSE(shipped.empty()) << "examples/" << name << ext << " is missing";
      EXPECT_EQ(testing::file_text(out), shipped)
          << "examples/" << name << ext << " differs from `plastivox export --demo " << name
          << "`; regenerate it";
    }
  EXPECT_EQ(cli("export --demo dodecahedron --out " + path("x.json")).status, 1);
  EXPECT_EQ(cli("export --demo pi --out " + path("x.txt")).status, 2);
}

TEST(ExamplesBodies, BodyPlanExamplesAreClassifiedAsNamed) {
  const std::pair<const char*, analysis::BodyPlan> cases[] = {
      {"pi", analysis::BodyPlan::kPi},
      {"gamma", analysis::BodyPlan::kGamma},
      {"upsilon", analysis::BodyPlan::kUpsilon}};
  for (const auto& [name, plan] : cases) {
    const RobotFile f = read_robot_file(kExamples + "/" + name + ".json");
    const analysis::BodyPlanResult r = analysis::classify_body_plan(analysis::voxel_set(f.robot));
    EXPECT_EQ(r.plan, plan) << name << " classified as " << analysis::to_string(r.plan);
    EXPECT_GT(r.confidence, 0.9) << name;
  }
}

TEST(ExamplesBodies, WalkerFileSimulatesLikeTheBuiltInWalker) {
  const testing::Output builtin = cli("simulate --json");
  const testing::Output file = cli("simulate " + kExamples + "/walker.json --json");
  ASSERT_EQ(builtin.status, 0) << builtin.out;
  ASSERT_EQ(file.status, 0) << file.out;
  const auto hash = [](const std::string& out) {
    const size_t at = out.find("\"final_state_hash\"");
    return out.substr(at, out.find_first_of(",\n}", at) - at);
  };
  EXPECT_EQ(hash(file.out), hash(builtin.out));  // the value itself: golden_lives_test.cpp
}

}  // namespace
}  // namespace plastivox
