// The command-line contract of `plastivox hausdorff`, through the real binary: JSON output for
// the project's robot files and VXA, the rotation options, and one-line errors with non-zero
// exit codes on bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "plastivox/io/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

namespace fs = std::filesystem;

using testing::Output;

// Runs the CLI; stderr goes to `err_path` so stdout stays pure JSON.
Output run(const std::string& args, const std::string& err_path) {
  return testing::shell(std::string(PLASTIVOX_CLI) + " " + args + " 2>" + err_path);
}

class HausdorffCli : public testing::ScratchDirTest {
 protected:
  // A robot file holding the sites for which filled(x, y, z) is true, on a 10^3 lattice.
  template <class Filled>
  std::string robot(const std::string& name, Filled filled) const {
    RobotDef r = make_empty_robot(10, 10, 10);
    for (int z = 0; z < 10; ++z)
      for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 10; ++x)
          if (filled(x, y, z)) {
            r.present[r.site(x, y, z)] = 1;
            r.stiffness[r.site(x, y, z)] = 1e9;
          }
    write_robot_file(path(name), r);
    return path(name);
  }

  Output hausdorff(const std::string& args) { return run("hausdorff " + args, path("stderr")); }
  std::string stderr_text() const {
    std::ifstream in(path("stderr"));
    return std::string((std::istreambuf_iterator<char>(in)), {});
  }

  fs::path dir_;
};

TEST_F(HausdorffCli, PrintsTheDistanceAsJson) {
  // Two 1x1x1 voxels three apart along x: d_H = 3 as placed.
  const std::string a =
      robot("a.json", [](int x, int y, int z) { return x == 0 && y == 0 && z == 0; });
  const std::string b =
      robot("b.json", [](int x, int y, int z) { return x == 3 && y == 0 && z == 0; });
  const Output o = hausdorff(a + " " + b + " --rotations none --json");
  ASSERT_EQ(o.status, 0) << stderr_text();
  const nlohmann::json j = nlohmann::json::parse(o.out);
  EXPECT_EQ(j["distance"].get<double>(), 3.0);
  EXPECT_EQ(j["distance_squared"].get<int>(), 9);
  EXPECT_EQ(j["rotations"], "none");
  EXPECT_EQ(j["translation_search"], "none");
  EXPECT_EQ(j["units"], "voxel lengths");
  // The full search moves B onto A.
  const nlohmann::json all =
      nlohmann::json::parse(hausdorff(a + " " + b + " --rotations all --json").out);
  EXPECT_EQ(all["distance"].get<double>(), 0.0);
  EXPECT_EQ(all["translation_search"], "integer");
  EXPECT_EQ(all["rotation"]["of"].get<int>(), 24);
}

TEST_F(HausdorffCli, PaperOrientationsFindAQuarterTurnedCopy) {
  // An L in the xy plane and the same L turned by +90 deg about z inside the lattice.
  const std::string a = robot("l.json", [](int x, int y, int z) {
    return z == 0 && ((x < 6 && y == 0) || (x == 0 && y < 3));
  });
  const std::string b = robot("l_turned.json", [](int x, int y, int z) {
    // (x, y) -> (9 - y, x)
    const int ox = y, oy = 9 - x;
    return z == 0 && ((ox < 6 && oy == 0) || (ox == 0 && oy < 3));
  });
  const nlohmann::json none =
      nlohmann::json::parse(hausdorff(a + " " + b + " --rotations none --json").out);
  EXPECT_GT(none["distance"].get<double>(), 0.0);
  // B must be turned back by -90 deg, which is 270 deg about z: orientation index 6.
  const Output o = hausdorff(a + " " + b + " --json");  // default: paper
  ASSERT_EQ(o.status, 0) << stderr_text();
  const nlohmann::json paper = nlohmann::json::parse(o.out);
  EXPECT_EQ(paper["rotations"], "paper");
  EXPECT_EQ(paper["distance"].get<double>(), 0.0);
  EXPECT_EQ(paper["rotation"]["index"].get<int>(), 6);
}

TEST_F(HausdorffCli, ReadsVxa) {
  const std::string vxa = testing::data_dir() + "/vxa/walker-none.vxa";
  const Output o = hausdorff(vxa + " " + vxa + " --json");
  ASSERT_EQ(o.status, 0) << stderr_text();
  EXPECT_EQ(nlohmann::json::parse(o.out)["distance"].get<double>(), 0.0);
  const std::string cube = testing::data_dir() + "/vxa/settle-cube-1e9.vxa";
  const Output text = hausdorff(vxa + " " + cube);
  ASSERT_EQ(text.status, 0) << stderr_text();
  EXPECT_NE(text.out.find("d_H = "), std::string::npos) << text.out;
}

TEST_F(HausdorffCli, BadInputGivesOneLineErrorsAndNonZeroExit) {
  const std::string a = robot("a.json", [](int x, int, int) { return x < 2; });
  const std::string empty = robot("empty.json", [](int, int, int) { return false; });
  std::ofstream(path("junk.json")) << "not json";
  struct Case {
    std::string args;
    int status;
    std::string says;
  };
  const Case cases[] = {
      {a, 2, "expected two robot files"},
      {a + " " + path("missing.json"), 1, "missing.json"},
      {a + " " + path("junk.json"), 1, "junk.json"},
      {a + " " + empty, 1, "no voxels"},
      {a + " " + a + " --rotations sideways", 2, "sideways"},
      {a + " " + a + " --translation half", 2, "--translation"},
      {a + " " + a + " --colour red", 2, "unknown option"},
  };
  for (const Case& c : cases) {
    const Output o = hausdorff(c.args);
    EXPECT_EQ(o.status, c.status) << c.args;
    EXPECT_TRUE(o.out.empty()) << c.args << ": " << o.out;
    const std::string err = stderr_text();
    EXPECT_NE(err.find(c.says), std::string::npos) << c.args << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << c.args << ": " << err;
  }
}

}  // namespace
}  // namespace plastivox
