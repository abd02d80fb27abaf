// plastivox render / video / gallery through the binary: outputs, exit codes, one-line
// errors and no file left behind on failure.
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/video_writer.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

class RenderCli : public testing::ScratchDirTest {
 protected:
  void SetUp() override {
    testing::ScratchDirTest::SetUp();
    write_robot_file(path("cube.json"), demo_cube(2, 1e7));
  }
  // plastivox COMMAND cube.json --out OUT OPTIONS, OUT in the scratch folder.
  testing::Output draw(const std::string& command, const std::string& out,
                       const std::string& options = "") const {
    return cli(command + " " + path("cube.json") + " --out " + path(out) + " " + options);
  }
  int files() const {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) n += e.is_regular_file();
    return n;
  }
};

TEST_F(RenderCli, RenderWritesAPngOfTheRequestedSizeWithEachAntialiasing) {
  for (const std::string mode : {"edge", "msaa", "none"}) {
    const auto r =
        draw("render", "f.png", "--time 0.1 --size 80x60 --color phase --antialias " + mode);
    ASSERT_EQ(r.status, 0) << mode << ": " << r.out;
    const render::Image img = render::read_png(path("f.png"));
    EXPECT_EQ(img.width, 80) << mode;
    EXPECT_EQ(img.height, 60) << mode;
  }
}

// Refusals: the exit status (2 for a usage error), a message naming the problem, and nothing
// written beside the robot.
TEST_F(RenderCli, RefusalsNameTheProblemAndWriteNothing) {
  const struct {
    std::string command, out, options;
    int status;
    std::string message;
  } cases[] = {
      {"render", "f.png", "--color jet", 2, "unknown colour mode 'jet'"},
      {"video", "v.mp4", "--size 64x48 --end 0.1 --antialias smooth", 2,
       "--antialias expects edge, msaa or none"},
      {"render", "no/dir/f.png", "", 1, "no/dir/f.png"},
      {"gallery", "g.png", path("missing.h5") + " --size 400x200", 1, "missing.h5"},
      // A name the PNG bytes would not match (it used to write PNG under .jpg).
      {"render", "f.jpg", "", 2, "--out " + path("f.jpg") + ": render writes PNG only"},
      {"render", "f.JPEG", "", 2, "render writes PNG only; name the file .png"},
      {"gallery", "g.jpg", path("missing.h5"), 2,
       "--out " + path("g.jpg") + ": gallery writes PNG only"},
  };
  for (const auto& c : cases) {
    const auto r = draw(c.command, c.out, c.options);
    EXPECT_EQ(r.status, c.status) << c.command << " " << c.options << ": " << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << r.out;
    EXPECT_EQ(files(), 1) << c.command << " " << c.options;
  }
}

// A life ends at its first step past the duration (5.2 s here): that step's time, the
// simulation's sim_time, is the life's last frame and renders; a time clearly past the end is
// refused in one line, before anything is simulated.
TEST_F(RenderCli, TheLifesOwnEndTimeRenders) {
  const auto sim = testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + path("cube.json") +
                                  " --json 2>/dev/null");
  const nlohmann::json j = nlohmann::json::parse(sim.out);
  const double end = j.at("sim_time").get<double>();
  ASSERT_GT(end, 5.2);
  char at[40];
  std::snprintf(at, sizeof at, "%.17g", end);
  auto r = draw("render", "end.png", std::string("--size 64x48 --antialias none --time ") + at);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(path("end.png")));
  r = draw("render", "mid.png", "--size 64x48 --antialias none --time 5.2000001");
  EXPECT_EQ(r.status, 0) << r.out;
  r = draw("render", "late.png", "--size 64x48 --time 6.2");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("render: error: " + path("cube.json") +
                       ": time 6.2 s is outside the life [0, 5.2] s (it ends at its first step "
                       "past 5.2 s)\n"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("late.png")));
}

TEST_F(RenderCli, PngNamesInAnyCaseAreWritten) {
  const auto r = draw("render", "f.PNG", "--size 32x24 --samples 1");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(render::read_png(path("f.PNG")).width, 32);
}

// view refuses an option that applies to none of its inputs, in one line, as export does
// (they used to be ignored: --fps for a recorded life, --generation for a robot).
TEST_F(RenderCli, ViewRefusesOptionsThatDoNotApplyToItsInputs) {
  PhysicsDef short_life;
  short_life.duration = 0.3;
  short_life.settle_time = 0.1;
  write_robot_file(path("walker.json"), demo_walker(), &short_life);
  const std::string life = path("life.h5"), robot = path("walker.json");
  const auto recorded = cli("simulate " + robot + " --record " + life);
  ASSERT_EQ(recorded.status, 0) << recorded.out;
  const struct {
    std::string inputs, options, message;
  } cases[] = {
      {life, "--fps 10", "--fps applies to a robot or a results file's champion, simulated here"},
      {life, "--fps 10", "; " + life + " is a recorded life"},
      {robot, "--generation 3",
       "--generation applies to a results file (.h5); " + robot + " is a robot"},
      {life, "--generation 0", "; " + life + " is a recorded life"},
      {life + " " + robot, "--generation 3", "; none of the 2 inputs is one"},
  };
  for (const auto& c : cases) {
    const auto r = cli("view " + c.inputs + " --out " + path("page.html") + " " + c.options);
    EXPECT_EQ(r.status, 2) << c.inputs << " " << c.options << ": " << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;
    EXPECT_FALSE(std::filesystem::exists(path("page.html")));
  }
  // Where it applies to one of the inputs, it is taken.
  const auto ok = cli("view " + life + " " + robot + " --fps 10 --out " + path("page.html"));
  EXPECT_EQ(ok.status, 0) << ok.out;
}

TEST_F(RenderCli, VideoWritesADecodableMp4) {
  const auto r = draw("video", "v.mp4", "--size 64x48 --fps 20 --end 0.3 --samples 1 --no-overlay");
  ASSERT_EQ(r.status, 0) << r.out;
  const render::VideoInfo info = render::probe_video(path("v.mp4"));
  EXPECT_EQ(info.frames, 6);
  EXPECT_EQ(info.width, 64);
  EXPECT_EQ(info.height, 48);
  EXPECT_NEAR(info.duration_s, 0.3, 0.051);
  EXPECT_EQ(files(), 2);
}

TEST_F(RenderCli, GalleryStiffnessRangeOption) {
  const std::string g = "gallery " + path("cube.json") + " --size 400x200 --samples 1 --out " +
                        path("g.png") + " --e0-range ";
  for (const std::string bad : {"1e6", "1e9,1e6", "0,1e9", "a,b"}) {
    const auto r = cli(g + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.out;
    EXPECT_NE(r.out.find("--e0-range"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line: " << r.out;
  }
  const auto both = cli(g + "1e6,1e9 --color-range paper");
  EXPECT_EQ(both.status, 2) << both.out;
  EXPECT_EQ(files(), 1);
  // The range is used and printed (so another gallery can be given the same one).
  const auto ok = cli(g + "1e6,1e9");
  ASSERT_EQ(ok.status, 0) << ok.out;
  EXPECT_NE(ok.out.find("E0 colour range 1e+06,1e+09 Pa"), std::string::npos) << ok.out;
  const auto data = draw("gallery", "d.png", "--size 400x200 --samples 1");
  ASSERT_EQ(data.status, 0) << data.out;
  EXPECT_NE(data.out.find("E0 colour range 1e+07,2e+07 Pa"), std::string::npos) << data.out;
}

// Sizes the renderer cannot take are refused before anything is simulated or allocated, in one
// line naming the size (issue 40: render --size 16384x16384 reached 3.2 GB before OpenGL
// refused it; figures --size 8192x8192 drew every panel for 35 s before refusing the combined
// figure; gallery --size 16384x16384 failed after simulating, naming no option).
TEST_F(RenderCli, OversizedImagesAreRefusedBeforeAnyWork) {
  const auto one_line = [](const testing::Output& r) {
    return r.out.find('\n') == r.out.size() - 1;
  };
  auto r = draw("render", "f.png", "--size 16384x16384");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("image size 16384x16384 with 4 sample(s) a pixel"), std::string::npos)
      << r.out;
  EXPECT_TRUE(one_line(r)) << r.out;
  r = draw("gallery", "g.png", "--size 16384x16384");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_EQ(r.out.rfind("plastivox gallery: --size 16384x16384: ", 0), 0u) << r.out;
  EXPECT_TRUE(one_line(r)) << r.out;
  EXPECT_EQ(files(), 1);  // nothing written
  // The limit itself: 8K UHD with 4x multisampling fits, 16384 x 16384 with one sample does not.
  EXPECT_NO_THROW(render::check_render_target(7680, 4320, 4));
  EXPECT_THROW(render::check_render_target(16384, 16384, 0), render::RenderError);
  EXPECT_THROW(render::check_render_target(16385, 10, 1), render::RenderError);
}

}  // namespace
}  // namespace plastivox
