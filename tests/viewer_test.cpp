// The in-browser 3-D viewer (issue 20): the packed life's size and layout, and the page in
// headless Chromium with software WebGL (SwiftShader): no console errors, a canvas that is not
// blank, a different image at the end of the life, the displacement shown at the end equal
// to the life's fitness, every voxel decoded as recorded, and no network needed.
#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

using testing::shell;

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

// A life that sinks through the floor is drawn to its end, so the fall can be watched, and
// keeps the fitness its rule gives it: 0 where sunk lives are invalid (the default).
TEST(ViewerItem, ASunkLifeIsShownToItsEndWithTheFitnessOfItsRule) {
  const RobotDef robot = testing::block(3, 3, 3, 1e5);  // soft and heavy: it falls through
  PhysicsDef physics = testing::passive_physics();
  physics.duration = 0.5;
  ASSERT_TRUE(physics.sinking_invalid);
  SimResult verdict = simulate(compile(robot, physics));
  judge_life(physics, verdict);
  ASSERT_EQ(verdict.floor_health, FloorHealth::kSank);
  ASSERT_EQ(verdict.status, SimStatus::kUnstable);
  for (const bool invalid : {true, false}) {
    physics.sinking_invalid = invalid;
    const render::LifeSource source =
        render::simulated_life_source("soft-block", robot, physics, "");
    const render::ShownLife shown = render::show_life(source, 30);
    EXPECT_EQ(shown.failure, "") << invalid;
    ASSERT_FALSE(shown.recording.frames.empty());
    EXPECT_GT(shown.recording.frames.back().time, source.physics.duration);
    EXPECT_LT(shown.recording.frames.back().pos[0].z(), -2 * 0.01);  // under the floor
    if (invalid)
      EXPECT_EQ(shown.info.fitness, 0.0);
    else
      EXPECT_GT(shown.info.fitness, 2.0);
  }
}

TEST(ViewerPack, ATenCubedChampionAtThirtyFramesPerSecondFitsInThreeMegabytes) {
  const Synthetic s = synthetic_block();
  render::ViewerItem life;
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

// A recording with the actuation signal packs one more byte per voxel and frame after the
// rest, each the signal over [-1, 1]; the page's scales include actuation either way.
TEST(ViewerPack, TheActuationSignalFollowsWhenRecorded) {
  Synthetic s = synthetic_block();
  s.rec.control = true;
  for (Frame& f : s.rec.frames)
    for (int i = 0; i < s.model.n; ++i) f.actuation.push_back(std::sin(f.time + i));
  render::ViewerItem life;
  life.model = &s.model;
  life.recording = &s.rec;
  const std::string packed = render::pack_life(life);
  const size_t n = 1000, frames = 157;
  const size_t body = 60 + 8 * n + 20 * frames + render::kPackedBytesPerVoxelFrame * n * frames;
  ASSERT_EQ(packed.size(), body + n * frames);
  for (const size_t k : {0ul, 100ul})
    for (const size_t i : {0ul, 999ul}) {
      const double u = static_cast<uint8_t>(packed[body + k * n + i]) / 255.0 * 2 - 1;
      EXPECT_NEAR(u, s.rec.frames[k].actuation[i], 1.0 / 255) << k << " " << i;
    }
  const size_t embedded = render::base64(packed).size() + render::life_meta_json(life).size();
  EXPECT_LT(embedded, 3'000'000u) << embedded;  // still within the issue's 3 MB
  const auto meta = nlohmann::json::parse(render::life_meta_json(life));
  EXPECT_EQ(meta["scales"]["actuation"]["lo"], -1);
  EXPECT_EQ(meta["scales"]["actuation"]["map"], "diverging");
}

class ViewerPage : public testing::ScratchDirTest {
 protected:
  // Opens `html` with `probe` (a <script>) added at the end of its body in headless Chromium
  // and returns the value the probe left in the body's attribute `attribute` ("" if none).
  std::string probe_page(const std::string& chromium, std::string html, const std::string& probe,
                         const std::string& attribute) {
    html.insert(html.rfind("</body>"), probe);
    write_file_atomic(path("check.html"), html);
    const auto dom = shell(chromium + "--window-size=1000,900 --dump-dom file://" +
                           path("check.html") + " 2>/dev/null");
    EXPECT_EQ(dom.status, 0);
    return testing::dom_attribute(dom.out, attribute);
  }
};

TEST_F(ViewerPage, ReplaysALifeInHeadlessChromiumWithNoNetwork) {
  const std::string chromium = testing::headless_chromium(path("profile"));
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium); viewer not checked";
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
  physics.sinking_invalid = false;  // soft and heavy, it sinks: scored, the authors' rule
  write_robot_file(path("block.json"), robot, &physics);
  const auto sim =
      shell(std::string(PLASTIVOX_CLI) + " simulate " + path("block.json") + " --json 2>/dev/null");
  ASSERT_EQ(sim.status, 0) << sim.out;
  const double fitness = nlohmann::json::parse(sim.out).at("fitness").get<double>();
  ASSERT_GT(fitness, 0.001);
  const auto view = cli("view " + path("block.json") + " --out " + path("page.html"));
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
  const auto dom =
      shell(chromium + "--window-size=1000,900 --enable-logging=stderr --v=0 --dump-dom file://" +
            path("check.html") + " 2>" + path("console.log"));
  ASSERT_EQ(dom.status, 0) << dom.out;
  const std::string console = read_file_bytes(path("console.log"));
  for (const char* bad : {"Uncaught", "Failed to load resource", "ERR_", "WebGL: "})
    EXPECT_EQ(console.find(bad), std::string::npos) << bad << " in:\n" << console;
  const std::string text = testing::dom_attribute(dom.out, "data-probe");
  ASSERT_FALSE(text.empty()) << dom.out;
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

// The camera stays above the floor: a mouse drag that would swing it under the floor stops a
// degree above the target's horizon, and a target below the floor (the follow camera on a
// body that sank) is lifted onto it, the camera with it. The stimulus colour bar of a stress
// life (stress is >= 0) runs from 0 on the sequential map.
TEST_F(ViewerPage, CameraCannotOrbitUnderTheFloor) {
  const std::string chromium = testing::headless_chromium(path("profile"));
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium); viewer not checked";
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = Treatment::kStress;
  physics.duration = 0.3;
  physics.settle_time = 0.1;
  physics.sinking_invalid = false;  // soft and heavy, it sinks: scored, the authors' rule
  write_robot_file(path("block.json"), testing::block(3, 3, 2, 1e7), &physics);
  ASSERT_EQ(cli("view " + path("block.json") + " --out " + path("page.html")).status, 0);
  const std::string probe = R"(<script>
(function () {
  const v = plastivoxViewer.viewer, c = v.canvas, out = { limit: v.controls.maxPolarAngle };
  const elevation = () => { const d = v.camera.position.clone().sub(v.controls.target);
    return Math.asin(d.z / d.length()) * 180 / Math.PI; };
  const drag = (dy) => {  // the left button held while the mouse moves by dy pixels
    c.dispatchEvent(new MouseEvent("mousedown", { button: 0, clientX: 400, clientY: 300 }));
    for (let k = 1; k <= 20; ++k)
      document.dispatchEvent(new MouseEvent("mousemove", { clientX: 400, clientY: 300 + dy * k / 20 }));
    document.dispatchEvent(new MouseEvent("mouseup", { button: 0, clientX: 400, clientY: 300 + dy }));
  };
  out.start = { z: v.camera.position.z, elevation: elevation() };
  drag(-5000);  // upwards: swings the camera down, and under the floor were it allowed
  out.dragged = { z: v.camera.position.z, elevation: elevation(), target: v.controls.target.z };
  drag(300);  // back up a little: the drag still works
  out.back = { elevation: elevation() };
  v.controls.target.z = -0.05;
  v.controls.update();
  out.sunk = { z: v.camera.position.z, target: v.controls.target.z, elevation: elevation() };
  const s = v.life.meta.scales.stimulus;
  out.stimulus = { lo: s.lo, hi: s.hi, map: s.map, first: s.ticks[0].label };
  document.body.setAttribute("data-floor", JSON.stringify(out));
})();
</script>)";
  const std::string text =
      probe_page(chromium, read_file_bytes(path("page.html")), probe, "data-floor");
  ASSERT_FALSE(text.empty());
  const nlohmann::json out = nlohmann::json::parse(text);
  EXPECT_LT(out["limit"].get<double>(), std::acos(0.0));
  EXPECT_NEAR(out["start"]["elevation"].get<double>(), 25, 0.5);  // the default view
  // Dragged as far down as it goes: a degree above the horizon of a target above the floor.
  EXPECT_NEAR(out["dragged"]["elevation"].get<double>(), 1, 0.01) << out.dump();
  EXPECT_GT(out["dragged"]["target"].get<double>(), 0);
  EXPECT_GT(out["dragged"]["z"].get<double>(), out["dragged"]["target"].get<double>());
  EXPECT_GT(out["back"]["elevation"].get<double>(), 5) << out.dump();
  // A target below the floor is lifted onto it; the camera stays above.
  EXPECT_DOUBLE_EQ(out["sunk"]["target"].get<double>(), 0);
  EXPECT_GT(out["sunk"]["z"].get<double>(), 0) << out.dump();
  EXPECT_EQ(out["stimulus"]["lo"].get<double>(), 0);
  EXPECT_GT(out["stimulus"]["hi"].get<double>(), 0);
  EXPECT_EQ(out["stimulus"]["map"], "sequential");
  EXPECT_EQ(out["stimulus"]["first"], "0");
}

// Where the body is in an image and which colours it shows where: the bounding box of the
// saturated (body) pixels, and per hue bin (45 degrees) its share of them and its centroid in
// box coordinates. Lighting scales a face's colour but keeps its hue, so the renderer's and
// the viewer's pictures of one pose agree on these when the same voxels are visible.
struct Layout {
  int body = 0;
  double aspect = 0;  // box width / height
  double share[8] = {};
  double cx[8] = {}, cy[8] = {};
};
Layout layout_of(const std::vector<uint8_t>& rgb, int w, int h) {  // rows top-down
  Layout out;
  int x0 = w, x1 = -1, y0 = h, y1 = -1;
  auto body = [&](int i, double* hue) {
    const double r = rgb[3 * i], g = rgb[3 * i + 1], b = rgb[3 * i + 2];
    const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
    if (mx - mn < 60) return false;
    double hh = mx == r   ? (g - b) / (mx - mn)
                : mx == g ? 2 + (b - r) / (mx - mn)
                          : 4 + (r - g) / (mx - mn);
    *hue = std::fmod(60 * hh + 360, 360);
    return true;
  };
  double hue = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (body(y * w + x, &hue)) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        ++out.body;
      }
  if (out.body == 0) return out;
  out.aspect = (x1 - x0 + 1.0) / (y1 - y0 + 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (body(y * w + x, &hue)) {
        const int k = std::min(7, static_cast<int>(hue / 45));
        out.share[k] += 1.0 / out.body;
        out.cx[k] += (x - x0) / (x1 - x0 + 1.0);
        out.cy[k] += (y - y0) / (y1 - y0 + 1.0);
      }
  for (int k = 0; k < 8; ++k)
    if (out.share[k] > 0) {
      out.cx[k] /= out.share[k] * out.body;
      out.cy[k] /= out.share[k] * out.body;
    }
  return out;
}

// The golden check: the viewer's first frame in congenital colours against the renderer's
// PNG of the same robot at t = 0 (same azimuth and elevation, follow camera): the same body
// outline and the same colours in the same places, to a tolerance (not pixel for pixel).
TEST_F(ViewerPage, FirstFrameHasTheRenderersLayout) {
  const std::string chromium = testing::headless_chromium(path("profile"));
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium); viewer not checked";
  // An L of 5 x 2 x 1 plus a 1 x 2 x 2 tower at one end, congenital stiffness rising along
  // x: a layout that a mirror or a swapped axis would change.
  RobotDef robot = testing::block(5, 2, 3, 1e7);
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 5; ++x) {
        const int s = robot.site(x, y, z);
        robot.present[s] = z == 0 || x == 4;
        robot.stiffness[s] = 1e6 * std::pow(10.0, x);
      }
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = Treatment::kNone;
  physics.duration = 0.2;
  physics.settle_time = 0.1;
  physics.sinking_invalid = false;  // its 1e6 Pa end sinks: scored, the authors' rule
  write_robot_file(path("l.json"), robot, &physics);
  ASSERT_EQ(cli("view " + path("l.json") + " --out " + path("page.html")).status, 0);
  ASSERT_EQ(cli("render " + path("l.json") + " --time 0 --color congenital --no-overlay " +
                "--camera follow --size 960x540 --out " + path("frame.png"))
                .status,
            0);
  // The viewer's frame 0, every other pixel, as hex RGB rows bottom-up (WebGL's order).
  const std::string probe = R"(<script>
(function () {
  const v = plastivoxViewer.viewer, px = v.pixels(), W = 960, H = 540, hex = [];
  for (let y = 0; y < H; y += 2) for (let x = 0; x < W; x += 2) { const i = 4 * (y * W + x);
    hex.push(((1 << 24) | (px[i] << 16) | (px[i + 1] << 8) | px[i + 2]).toString(16).slice(1)); }
  document.body.setAttribute("data-frame", hex.join(""));
})();
</script>)";
  const std::string hex =
      probe_page(chromium, read_file_bytes(path("page.html")), probe, "data-frame");
  const int w = 480, h = 270;
  ASSERT_EQ(hex.size(), static_cast<size_t>(6 * w * h));
  std::vector<uint8_t> viewer(3 * w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        viewer[3 * ((h - 1 - y) * w + x) + c] =
            static_cast<uint8_t>(std::stoi(hex.substr(6 * (y * w + x) + 2 * c, 2), nullptr, 16));
  const render::Image png = render::read_png(path("frame.png"));
  ASSERT_EQ(png.width, 960);
  std::vector<uint8_t> rendered(3 * w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        rendered[3 * (y * w + x) + c] = png.rgba[4 * (2 * y * 960 + 2 * x) + c];
  const Layout a = layout_of(viewer, w, h), b = layout_of(rendered, w, h);
  ASSERT_GT(a.body, 500) << "no body in the viewer's frame";
  ASSERT_GT(b.body, 500) << "no body in the renderer's frame";
  EXPECT_NEAR(a.aspect, b.aspect, 0.2 * b.aspect);
  int bins = 0;
  for (int k = 0; k < 8; ++k) {
    if (a.share[k] < 0.05 && b.share[k] < 0.05) continue;
    ++bins;
    // The viewer's camera stands further off (the body smaller, less perspective), so the
    // tower's side shows a little more: 0.64 against 0.51 of the body in the yellow bin.
    EXPECT_NEAR(a.share[k], b.share[k], 0.15) << "hue bin " << k;
    if (a.share[k] < 0.02 || b.share[k] < 0.02) continue;
    EXPECT_NEAR(a.cx[k], b.cx[k], 0.12) << "hue bin " << k;
    EXPECT_NEAR(a.cy[k], b.cy[k], 0.12) << "hue bin " << k;
  }
  EXPECT_GE(bins, 3) << "the congenital colours should span several hues";
}

}  // namespace
}  // namespace plastivox
