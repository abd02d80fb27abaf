// The in-browser 3-D viewer (issue 20): the packed life's size and layout, and the page in
// headless Chromium with software WebGL (SwiftShader): no console errors, a canvas that is not
// blank, a different image at the end of the life, the displacement shown at the end equal
// to the life's fitness, every voxel decoded as recorded, and no network needed.
#include <cmath>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/atomic_file.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::shell;

testing::Output run(const std::string& args) {
  return shell(std::string(PLASTIVOX_CLI) + " " + args + " 2>&1");
}

// A synthetic life of a 10x10x10 block: 5.2 s at 30 frames per second (157 frames), every
// voxel moving and turning, so no field packs to a constant.
struct Synthetic {
  Model model;
  Recording rec;
};
Synthetic synthetic_block() {
  Synthetic s;
  s.model = compile(testing::block(10, 10, 10, 1e7), preset_gecco2018_code());
  s.rec.fps = 30;
  for (int k = 0; k <= 156; ++k) {
    Frame f;
    f.time = k / 30.0;
    for (int i = 0; i < s.model.n; ++i) {
      const double w = 0.1 * f.time + 0.001 * i;
      f.pos.push_back(s.model.rest_pos[i] + Vec3(0.05 * f.time, 0.002 * std::sin(w), 0.001));
      f.orient.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(w, Vec3(1, 2, 3).normalized())));
      f.size.push_back(0.01 * (1 + 0.1 * std::sin(20 * f.time)));
      f.stiffness.push_back(1e7 * (1 + 0.5 * std::sin(w)));
      f.stimulus.push_back(1e4 * std::cos(w));
    }
    s.rec.frames.push_back(std::move(f));
  }
  return s;
}

TEST(ViewerPack, ATenCubedChampionAtThirtyFramesPerSecondFitsInThreeMegabytes) {
  const Synthetic s = synthetic_block();
  render::ViewerLife life;
  life.model = &s.model;
  life.recording = &s.rec;
  const std::string packed = render::pack_life(life);
  const size_t n = 1000, frames = 157;
  EXPECT_EQ(packed.size(),
            60 + 8 * n + 20 * frames + render::kPackedBytesPerVoxelFrame * n * frames);
  EXPECT_EQ(packed.substr(0, 4), "PVL1");
  // As embedded in a page (base64) with its colour scales: under the issue's 3 MB.
  const size_t embedded = render::base64(packed).size() + render::life_meta_json(life).size();
  EXPECT_LT(embedded, 3'000'000u) << embedded;
  EXPECT_EQ(render::base64("plastivox"), "cGxhc3Rpdm94");
  EXPECT_EQ(render::base64("pv"), "cHY=");
}

class ViewerPage : public testing::ScratchDirTest {};

TEST_F(ViewerPage, ReplaysALifeInHeadlessChromiumWithNoNetwork) {
  const auto which = shell("command -v chromium 2>/dev/null");
  if (which.status != 0 || which.out.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium); viewer not checked";
  const std::string chromium = which.out.substr(0, which.out.find('\n'));
  // A 3x3x2 walker-ish block with actuation and stress development, a 0.6 s life.
  RobotDef robot = testing::block(3, 3, 2, 1e7);
  for (size_t s = 0; s < robot.phase.size(); ++s) {
    robot.phase[s] = 0.25 * (s % 4);
    robot.stiffness[s] = 1e7 * (1 + s % 5);  // five congenital colours
  }
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = Treatment::kStress;
  physics.duration = 0.6;
  physics.settle_time = 0.1;
  write_robot_file(path("block.json"), robot, &physics);
  const auto sim =
      shell(std::string(PLASTIVOX_CLI) + " simulate " + path("block.json") + " --json 2>/dev/null");
  ASSERT_EQ(sim.status, 0) << sim.out;
  const double fitness = nlohmann::json::parse(sim.out).at("fitness").get<double>();
  ASSERT_GT(fitness, 0.001);
  const auto view = run("view " + path("block.json") + " --out " + path("page.html"));
  ASSERT_EQ(view.status, 0) << view.out;
  std::string html = read_file_bytes(path("page.html"));
  // Nothing is fetched: no element loads anything from anywhere.
  EXPECT_EQ(html.find(" src=\""), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  // A probe after the viewer has started: pixels at t = 0 and, the time slider moved to the
  // end, there; what the readout
  // says there, and every voxel of the last frame decoded.
  const std::string probe = R"(<script>
(function () {
  const pv = plastivoxViewer, v = pv.viewer, b = document.body;
  const colours = (px) => { const s = new Set(); for (let i = 0; i < px.length; i += 4 * 7)
    s.add((px[i] << 16) | (px[i + 1] << 8) | px[i + 2]); return s.size; };
  const first = v.pixels();
  v.slider.value = v.slider.max;  // the time slider to the end, as a reader drags it
  v.slider.dispatchEvent(new Event("input"));
  const last = v.pixels();
  let changed = 0;
  for (let i = 0; i < first.length; i += 4)
    changed += first[i] !== last[i] || first[i + 1] !== last[i + 1] || first[i + 2] !== last[i + 2];
  const r = v.readout.dataset;
  const voxels = [];
  for (let i = 0; i < v.life.n; ++i) { const d = pv.decode(v.life.frames - 1, i);
    voxels.push([d.p[0], d.p[1], d.p[2], d.q[0], d.q[1], d.q[2], d.q[3], d.size]); }
  b.setAttribute("data-probe", JSON.stringify({ colours: colours(first), changed: changed,
    pixels: first.length / 4, displacement: +r.displacement, time: +r.time,
    frames: v.life.frames, text: v.readout.textContent, voxels: voxels }));
})();
</script>)";
  html.insert(html.rfind("</body>"), probe);
  write_file_atomic(path("check.html"), html);
  // Software WebGL; every host name unresolvable, as with the network off.
  const std::string flags =
      " --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
      "--host-resolver-rules='MAP * ~NOTFOUND' --disable-background-networking "
      "--disable-component-update --disable-sync --no-first-run --user-data-dir=" +
      path("profile") + " --window-size=1000,900 ";
  const auto dom = shell(chromium + flags + "--enable-logging=stderr --v=0 --dump-dom file://" +
                         path("check.html") + " 2>" + path("console.log"));
  ASSERT_EQ(dom.status, 0) << dom.out;
  const std::string console = read_file_bytes(path("console.log"));
  for (const char* bad : {"Uncaught", "Failed to load resource", "ERR_", "WebGL: "})
    EXPECT_EQ(console.find(bad), std::string::npos) << bad << " in:\n" << console;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom.out, m, std::regex("data-probe=\"([^\"]*)\""))) << dom.out;
  std::string text = m[1];
  for (size_t at; (at = text.find("&quot;")) != std::string::npos;) text.replace(at, 6, "\"");
  const nlohmann::json probe_out = nlohmann::json::parse(text);
  EXPECT_EQ(probe_out.at("pixels").get<int>(), 960 * 540);
  // Background, floor, grid and the body's faces in five congenital colours, lit.
  EXPECT_GT(probe_out.at("colours").get<int>(), 10) << "the canvas is (nearly) blank";
  EXPECT_GT(probe_out.at("changed").get<int>(), 200) << "the end of the life looks like its start";
  // The displacement shown at the end is the life's fitness, to 3 significant digits.
  const double shown = probe_out.at("displacement").get<double>();
  EXPECT_NEAR(shown, fitness, 5e-4 * fitness) << probe_out.at("text");
  EXPECT_GE(probe_out.at("time").get<double>(), 0.6);
  // Every voxel of the last frame decodes to the recorded pose (the same life, simulated
  // again here with the viewer's 30 frames per second).
  const Model model = compile(robot, physics);
  SimOptions options;
  options.record_fps = 30;
  const SimResult r = simulate(model, options);
  ASSERT_EQ(probe_out.at("frames").get<size_t>(), r.recording.frames.size());
  const Frame& end = r.recording.frames.back();
  double size_lo = 1, size_hi = 0;  // sizes are u8 over the life's range
  for (const Frame& f : r.recording.frames)
    for (double x : f.size) size_lo = std::min(size_lo, x), size_hi = std::max(size_hi, x);
  const auto& voxels = probe_out.at("voxels");
  ASSERT_EQ(voxels.size(), static_cast<size_t>(model.n));
  for (int i = 0; i < model.n; ++i) {
    const auto& d = voxels[i];
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(d[a].get<double>(), end.pos[i][a], 2e-6) << i;
    const Eigen::Quaterniond q(d[3].get<double>(), d[4].get<double>(), d[5].get<double>(),
                               d[6].get<double>());
    EXPECT_LT(q.angularDistance(end.orient[i]), 0.005) << i;
    EXPECT_NEAR(d[7].get<double>(), end.size[i], 0.51 * (size_hi - size_lo) / 255 + 1e-9) << i;
  }
}

}  // namespace
}  // namespace plastivox
