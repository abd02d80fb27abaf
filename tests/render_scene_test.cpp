// The renderer: colour maps, colour scales, pixel checks of single voxels and empty scenes,
// determinism, galleries, videos and bad input (render/).
#include <filesystem>
#include <fstream>
#include <iterator>

#include "plastivox/demo_robots.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/render_life.hpp"
#include "plastivox/render/video_writer.hpp"
#include "test_support.hpp"

namespace plastivox::render {
namespace {

using plastivox::testing::error_of;
using plastivox::testing::ScratchDirTest;

const uint8_t* pixel(const std::vector<uint8_t>& rgba, int width, int x, int y) {
  return rgba.data() + (static_cast<size_t>(y) * width + x) * 4;
}

int files_in(const std::filesystem::path& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

// A life of one robot under physics without actuation, captured at t = 0.
LifeSource source_of(const RobotDef& robot, Treatment treatment = Treatment::kNone) {
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = treatment;
  return simulated_life_source("inline", robot, physics, "");
}

FrameStyle small_style(int w, int h) {
  FrameStyle st;
  st.width = w;
  st.height = h;
  st.samples = 1;
  st.overlay = {false, false, false, false, false};
  return st;
}

// Straight down, parallel projection, flat colours: a voxel's pixels are exactly its colour.
FrameStyle flat_top_view(int w, int h) {
  FrameStyle st = small_style(w, h);
  st.orthographic = true;
  st.elevation_deg = 90;
  st.lit = false;
  return st;
}

// ---------------------------------------------------------------------------------------
// Colour maps and scales
// ---------------------------------------------------------------------------------------

TEST(RenderColormap, SequentialLightnessRisesInEqualPerceptualSteps) {
  const Colormap& m = Colormap::sequential();
  const auto& lab = m.lab();
  double min_step = 1e9, max_step = 0;
  for (size_t i = 1; i < lab.size(); ++i) {
    EXPECT_GT(lab[i][0], lab[i - 1][0]) << "lightness must rise at entry " << i;
    const double d =
        std::sqrt(std::pow(lab[i][0] - lab[i - 1][0], 2) + std::pow(lab[i][1] - lab[i - 1][1], 2) +
                  std::pow(lab[i][2] - lab[i - 1][2], 2));
    min_step = std::min(min_step, d);
    max_step = std::max(max_step, d);
  }
  EXPECT_LT(max_step / min_step, 1.1) << "steps " << min_step << " .. " << max_step;
  EXPECT_LT(lab.front()[0], 25);  // dark start, light end
  EXPECT_GT(lab.back()[0], 85);
}

TEST(RenderColormap, DivergingIsNeutralInTheMiddleAndSymmetricInLightness) {
  const Colormap& m = Colormap::diverging();
  const auto& lab = m.lab();
  const size_t n = lab.size();
  for (size_t i = 0; i < n / 2; ++i)
    EXPECT_NEAR(lab[i][0], lab[n - 1 - i][0], 1.0) << "entry " << i;
  const Rgb8 mid = m.at(0.5);
  EXPECT_LE(std::max({mid[0], mid[1], mid[2]}) - std::min({mid[0], mid[1], mid[2]}), 3);
  EXPECT_GT(m.at(0.0)[2], m.at(0.0)[0]);  // blue end
  EXPECT_GT(m.at(1.0)[0], m.at(1.0)[2]);  // red end
}

TEST(RenderColormap, CyclicMapWrapsAroundWithoutAJump) {
  const Colormap& m = Colormap::cyclic_map();
  EXPECT_EQ(m.at(0.0), m.at(1.0));
  EXPECT_EQ(m.at(0.25), m.at(1.25));
  EXPECT_EQ(m.clipped_entries(), 0);  // every hue fits in sRGB at this lightness and chroma
  const auto& lab = m.lab();
  for (const auto& c : lab) EXPECT_NEAR(c[0], lab[0][0], 1e-6);
}

TEST(RenderColorScale, ParsesModesAndRejectsUnknownNames) {
  EXPECT_EQ(parse_color_mode("change"), ColorMode::kChange);
  EXPECT_EQ(parse_color_mode("phase"), ColorMode::kPhase);
  try {
    parse_color_mode("jet");
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("'jet'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("congenital"), std::string::npos) << e.what();
  }
}

// --color stimulus: from 0 to the largest stimulus shown, rounded up to a 1-2-5 value; a signed
// stimulus (pressure is negative in tension) is symmetric about 0 on the diverging map.
TEST(RenderColorScale, StimulusSpansTheStimulusShown) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kContact;
  const Model model = compile(demo_cube(2, 1e8), d);
  Frame a, b;
  a.stimulus = {0, 0, 1.2e8, 3e7, 0, 0, 0, 0};
  b.stimulus = {0, 0, 1.7e8, 0, 0, 0, 0, 0};
  EXPECT_EQ(parse_color_mode("stimulus"), ColorMode::kStimulus);
  const ColorScale s = make_color_scale(ColorMode::kStimulus, model, {&a, &b});
  EXPECT_DOUBLE_EQ(s.lo, 0);
  EXPECT_DOUBLE_EQ(s.hi, 2e8);
  EXPECT_NE(s.title.find("contact"), std::string::npos) << s.title;
  EXPECT_EQ(&s.map(), &Colormap::sequential());
  EXPECT_DOUBLE_EQ(s.position(s.value(model, b, 2)), 0.85);
  const std::vector<Tick> ticks = s.ticks();
  ASSERT_GE(ticks.size(), 3u);
  EXPECT_EQ(ticks.front().label, "0");
  EXPECT_EQ(ticks.back().label, "2×10⁸");
  // Contact is >= 0 by definition: a stray negative value (none in a real life) takes the
  // bottom colour and does not turn the map two-sided.
  b.stimulus[5] = -4e8;
  const ColorScale stray = make_color_scale(ColorMode::kStimulus, model, {&a, &b});
  EXPECT_DOUBLE_EQ(stray.lo, 0);
  EXPECT_EQ(&stray.map(), &Colormap::sequential());
  EXPECT_DOUBLE_EQ(stray.position(stray.value(model, b, 5)), 0);
  // Pressure is signed (negative in tension): symmetric about 0 on the diverging map, even
  // when the frames shown hold no negative value, so 0 is always the neutral colour.
  d.treatment = Treatment::kPressure;
  const Model pressured = compile(demo_cube(2, 1e8), d);
  b.stimulus[5] = -4e8;
  const ColorScale signed_scale = make_color_scale(ColorMode::kStimulus, pressured, {&a, &b});
  EXPECT_DOUBLE_EQ(signed_scale.lo, -5e8);
  EXPECT_DOUBLE_EQ(signed_scale.hi, 5e8);
  EXPECT_EQ(&signed_scale.map(), &Colormap::diverging());
  EXPECT_EQ(signed_scale.ticks().front().label, "−5×10⁸");
  b.stimulus[5] = 0;
  const ColorScale positive = make_color_scale(ColorMode::kStimulus, pressured, {&a, &b});
  EXPECT_DOUBLE_EQ(positive.lo, -2e8);
  EXPECT_DOUBLE_EQ(positive.position(0), 0.5);
}

// Which stimuli can be negative (docs/plasticity.md): only pressure's.
TEST(RenderColorScale, OnlyPressureIsASignedStimulus) {
  for (const Treatment t : {Treatment::kNone, Treatment::kStress, Treatment::kStrain,
                            Treatment::kStrainEnergy, Treatment::kContact, Treatment::kKinetic})
    EXPECT_FALSE(stimulus_is_signed(t)) << to_string(t);
  EXPECT_TRUE(stimulus_is_signed(Treatment::kPressure));
}

TEST(RenderColorScale, PaperRangeTicksAreDecadesOverThePhysicsRange) {
  const Model model = compile(demo_cube(2, 1e8), preset_gecco2018_code());  // E in [1e5, 1e11]
  const ColorScale s = make_color_scale(ColorMode::kCongenital, model, {}, ColorRange::kPaper);
  EXPECT_NE(s.title.find("paper's range"), std::string::npos) << s.title;
  EXPECT_DOUBLE_EQ(s.lo, 5);
  EXPECT_DOUBLE_EQ(s.hi, 11);
  const std::vector<Tick> ticks = s.ticks();
  ASSERT_GE(ticks.size(), 3u);
  EXPECT_EQ(ticks.front().label, "10⁵");
  EXPECT_DOUBLE_EQ(ticks.front().t, 0.0);
  EXPECT_DOUBLE_EQ(ticks.back().t, 1.0);
  EXPECT_DOUBLE_EQ(s.position(std::log10(1e8)), 0.5);
}

// A 2x2x2 cube of E = e but voxel k of E = e_k, compiled with the paper's physics.
Model cube_with_one_voxel_at(double e, int k, double e_k) {
  RobotDef r = demo_cube(2, e);
  r.stiffness[k] = e_k;
  return compile(r, preset_gecco2018_code());
}

// The champions of the default study lie between about 1.6e9 and 4.8e10 Pa: the default
// (data) range is 1e9..5e10 with 1-2-5 ticks, not the paper's 1e5..1e11.
TEST(RenderColorScale, DataRangeIsTheValuesShownRoundedToReadableTicks) {
  const Model model = cube_with_one_voxel_at(1.6e9, 3, 4.8e10);
  const ColorScale s = make_color_scale(ColorMode::kCongenital, model, {});
  EXPECT_DOUBLE_EQ(s.lo, 9);
  EXPECT_DOUBLE_EQ(s.hi, std::log10(5e10));
  EXPECT_NE(s.title.find("range of the data"), std::string::npos) << s.title;
  std::vector<std::string> labels;
  for (const Tick& t : s.ticks()) labels.push_back(t.label);
  EXPECT_EQ(labels,
            (std::vector<std::string>{"10⁹", "2×10⁹", "5×10⁹", "10¹⁰", "2×10¹⁰", "5×10¹⁰"}));
  EXPECT_DOUBLE_EQ(s.ticks().front().t, 0.0);
  EXPECT_DOUBLE_EQ(s.ticks().back().t, 1.0);
  // The two robots' colours are far apart on this scale, close on the paper's.
  const ColorScale paper = make_color_scale(ColorMode::kCongenital, model, {}, ColorRange::kPaper);
  EXPECT_GT(s.position(std::log10(4.8e10)) - s.position(std::log10(1.6e9)), 0.8);
  EXPECT_LT(paper.position(std::log10(4.8e10)) - paper.position(std::log10(1.6e9)), 0.3);
}

TEST(RenderColorScale, DataRangeOfManyDecadesUsesDecadesAndAUniformRobotStillHasASpan) {
  const Model wide = cube_with_one_voxel_at(3e5, 1, 7e10);
  const ColorScale s = make_color_scale(ColorMode::kCongenital, wide, {});
  EXPECT_DOUBLE_EQ(s.lo, 5);
  EXPECT_DOUBLE_EQ(s.hi, 11);
  EXPECT_EQ(s.ticks().front().label, "10⁵");
  const Model uniform = compile(demo_cube(2, 1e8), preset_gecco2018_code());
  const ColorScale u = make_color_scale(ColorMode::kCongenital, uniform, {});
  EXPECT_DOUBLE_EQ(u.lo, 8);
  EXPECT_DOUBLE_EQ(u.hi, std::log10(2e8));
  // Current stiffness: the range of the frames' values, not of E0.
  Frame f;
  f.stiffness.assign(uniform.n, 1e8);
  f.stiffness[0] = 3e9;
  const ColorScale cur = make_color_scale(ColorMode::kStiffness, uniform, {&f});
  EXPECT_DOUBLE_EQ(cur.lo, 8);
  EXPECT_DOUBLE_EQ(cur.hi, std::log10(5e9));
  EXPECT_EQ(parse_color_range("paper"), ColorRange::kPaper);
  EXPECT_NE(error_of([] { parse_color_range("auto"); }).find("data or paper"), std::string::npos);
}

TEST(RenderColorScale, ChangePaperRangeIsTheWidestChangeThePhysicsAllows) {
  const Model model = compile(demo_cube(2, 1e8), preset_gecco2018_code());
  Frame f;
  f.stiffness.assign(model.n, 1e8);
  f.stiffness[0] = 3e8;
  const ColorScale s = make_color_scale(ColorMode::kChange, model, {&f}, ColorRange::kPaper);
  EXPECT_DOUBLE_EQ(s.hi, 6);
  EXPECT_DOUBLE_EQ(s.lo, -6);
  EXPECT_NE(s.title.find("paper's range"), std::string::npos) << s.title;
}

TEST(RenderColorScale, ChangeRangeIsSymmetricAndCoversEveryFrame) {
  const Model model = compile(demo_cube(2, 1e8), preset_gecco2018_code());
  Frame f;
  f.stiffness.assign(model.n, 1e8);
  f.stiffness[0] = 3e8;  // x3: the bar spans x1/3 .. x3
  const ColorScale s = make_color_scale(ColorMode::kChange, model, {&f});
  EXPECT_NEAR(s.hi, std::log10(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(s.lo, -s.hi);
  EXPECT_DOUBLE_EQ(s.position(0), 0.5);
}

// The issue's case: a life whose changes span x0.83 .. x4.4 gets a bar from x1/4.4 to x4.4
// (symmetric in log about x1, both ends labelled), not x0.1 .. x10; the largest change
// downwards sets the span when it is the larger one; tiny changes keep at least x1.01.
TEST(RenderColorScale, ChangeBarSpansWhatTheDataReach) {
  const Model model = compile(demo_cube(2, 1e8), preset_gecco2018_code());
  Frame f;
  f.stiffness.assign(model.n, 1e8);
  f.stiffness[0] = 0.83e8;
  f.stiffness[1] = 4.4e8;
  const ColorScale s = make_color_scale(ColorMode::kChange, model, {&f});
  EXPECT_NEAR(s.hi, std::log10(4.4), 1e-12);
  EXPECT_DOUBLE_EQ(s.lo, -s.hi);
  std::vector<std::string> labels;
  for (const Tick& t : s.ticks()) labels.push_back(t.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"×1/4.4", "×0.5", "×1", "×2", "×4.4"}));
  EXPECT_DOUBLE_EQ(s.ticks().front().t, 0.0);
  EXPECT_DOUBLE_EQ(s.ticks().back().t, 1.0);
  // x4.4 itself takes the top colour, x0.83 a colour a little below the middle.
  EXPECT_NEAR(s.position(std::log10(4.4)), 1.0, 1e-12);
  EXPECT_NEAR(s.position(std::log10(0.83)), 0.5 - 0.5 * std::log10(1 / 0.83) / std::log10(4.4),
              1e-12);
  // Downwards: x0.2 (and x1.5 up) -> x1/5 .. x5; rounding up to two digits: x4.43 -> x4.5.
  f.stiffness[0] = 0.2e8;
  f.stiffness[1] = 1.5e8;
  EXPECT_NEAR(make_color_scale(ColorMode::kChange, model, {&f}).hi, std::log10(5.0), 1e-12);
  f.stiffness[0] = 1e8;
  f.stiffness[1] = 4.43e8;
  EXPECT_NEAR(make_color_scale(ColorMode::kChange, model, {&f}).hi, std::log10(4.5), 1e-12);
  // Below x2 the digits are those of the change: x1.0123 -> x1.013; nothing -> x1.01.
  f.stiffness[1] = 1.0123e8;
  EXPECT_NEAR(make_color_scale(ColorMode::kChange, model, {&f}).hi, std::log10(1.013), 1e-12);
  f.stiffness[1] = 1e8;
  EXPECT_NEAR(make_color_scale(ColorMode::kChange, model, {&f}).hi, std::log10(1.01), 1e-12);
}

std::vector<std::string> change_labels(double hi) {
  ColorScale s;
  s.mode = ColorMode::kChange;
  s.lo = -hi;
  s.hi = hi;
  std::vector<std::string> out;
  for (const Tick& t : s.ticks()) {
    out.push_back(t.label);
    EXPECT_GE(t.t, 0.0);
    EXPECT_LE(t.t, 1.0);
    if (t.label == "×1") {
      EXPECT_DOUBLE_EQ(t.t, 0.5);
    }
  }
  return out;
}

TEST(RenderColorScale, ChangeTicksAreShortExactRatios) {
  using L = std::vector<std::string>;
  // Inner ticks are short ratios (x0.5, not x0.316); the ends carry the bar's exact span
  // unless a tick stands near (within 0.12 of the bar).
  EXPECT_EQ(change_labels(0.5), (L{"×1/3.162", "×0.5", "×1", "×2", "×3.162"}));
  EXPECT_EQ(change_labels(1), (L{"×0.1", "×0.2", "×0.5", "×1", "×2", "×5", "×10"}));
  EXPECT_EQ(change_labels(2), (L{"×0.01", "×0.1", "×1", "×10", "×100"}));
  EXPECT_EQ(change_labels(5), (L{"×10⁻⁴", "×0.01", "×1", "×100", "×10⁴"}));
  EXPECT_EQ(change_labels(0.2), (L{"×1/1.585", "×0.8", "×1", "×1.2", "×1.4", "×1.585"}));
  EXPECT_EQ(change_labels(0.1), (L{"×0.8", "×0.9", "×1", "×1.1", "×1.2"}));
  EXPECT_EQ(change_labels(0.005), (L{"×0.99", "×0.995", "×1", "×1.005", "×1.01"}));
  // Each tick sits at its ratio's own position on the log scale.
  ColorScale s;
  s.mode = ColorMode::kChange;
  s.lo = -0.5;
  s.hi = 0.5;
  EXPECT_NEAR(s.ticks()[1].t, (std::log10(0.5) + 0.5) / 1.0, 1e-12);  // after the end "×1/3.162"
}

// ---------------------------------------------------------------------------------------
// Pixels
// ---------------------------------------------------------------------------------------

// One voxel of E = 1e8 Pa seen from above with a parallel projection, flat shading: the
// pixel at its centre is exactly the colour bar's colour at 1e8 Pa, and that colour appears
// in the drawn colour bar at the height of 1e8.
TEST(RenderPixels, SingleVoxelHasTheColourBarColourAtItsCentre) {
  const int w = 240, h = 160;
  const FrameSet life = take_frame_set(source_of(demo_cube(1, 1e8)), {0.0});
  // The paper's fixed range, so 1e8 Pa sits in the middle of the bar.
  const ColorScale scale =
      make_color_scale(ColorMode::kCongenital, *life.model, {}, ColorRange::kPaper);
  FrameStyle st = flat_top_view(w, h);
  st.overlay.colorbar = true;
  FrameRenderer renderer(st);
  const std::vector<uint8_t> img = renderer.render(life, life.frames[0], scale, "none");
  const Rgb8 expected = scale.map().at(scale.position(8.0));
  const uint8_t* c = pixel(img, w, w / 2, h / 2);
  EXPECT_EQ(c[0], expected[0]);
  EXPECT_EQ(c[1], expected[1]);
  EXPECT_EQ(c[2], expected[2]);
  // Find the colour bar column (right quarter) and the rows holding exactly this colour.
  int found_row = -1, bar_x = -1;
  for (int y = 0; y < h && found_row < 0; ++y)
    for (int x = 3 * w / 4; x < w; ++x) {
      const uint8_t* p = pixel(img, w, x, y);
      if (p[0] == expected[0] && p[1] == expected[1] && p[2] == expected[2]) {
        found_row = y;
        bar_x = x;
        break;
      }
    }
  ASSERT_GE(found_row, 0) << "the voxel's colour is not in the colour bar";
  // It sits halfway between the bar's ends (1e8 is the middle of 1e5..1e11): the rows
  // nearest the map's two end colours, in the same column, bracket it symmetrically.
  auto distance = [&](int y, const Rgb8& c) {
    const uint8_t* p = pixel(img, w, bar_x, y);
    return std::abs(p[0] - c[0]) + std::abs(p[1] - c[1]) + std::abs(p[2] - c[2]);
  };
  const Rgb8 top = scale.map().at(1.0), bottom = scale.map().at(0.0);
  int top_row = 0, bottom_row = 0;
  for (int y = 0; y < h; ++y) {
    if (distance(y, top) < distance(top_row, top)) top_row = y;
    if (distance(y, bottom) < distance(bottom_row, bottom)) bottom_row = y;
  }
  EXPECT_LE(distance(top_row, top), 12);
  EXPECT_LE(distance(bottom_row, bottom), 12);
  ASSERT_GT(bottom_row, top_row);
  EXPECT_NEAR(found_row, 0.5 * (top_row + bottom_row), 2.0);
}

// Lit, the voxel's top face keeps the colour's hue: the centre pixel is within shading
// tolerance of the map colour in chromaticity (ratios of channels).
TEST(RenderPixels, LitVoxelKeepsItsColourWithinShadingTolerance) {
  const int w = 120, h = 90;
  const FrameSet life = take_frame_set(source_of(demo_cube(1, 1e6)), {0.0});
  const ColorScale scale = make_color_scale(ColorMode::kCongenital, *life.model, {});
  FrameStyle st = small_style(w, h);
  st.orthographic = true;
  st.elevation_deg = 90;
  FrameRenderer renderer(st);
  const std::vector<uint8_t> img = renderer.render(life, life.frames[0], scale, "none");
  const Rgb8 expected = scale.color(*life.model, life.frames[0], 0);
  const uint8_t* c = pixel(img, w, w / 2, h / 2);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(c[d], expected[d], 40) << "channel " << d;
}

TEST(RenderPixels, EmptySceneIsFloorOnly) {
  const int w = 160, h = 120;
  OffscreenContext ctx(w, h);
  SceneRenderer r(ctx);
  Scene scene;
  scene.samples = 1;
  scene.lit = false;
  scene.camera.distance = 0.3;
  r.draw(scene);
  const std::vector<uint8_t> flat = ctx.read_rgba();
  int floor = 0, sky = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = pixel(flat, w, x, y);
      const Rgb8 c{p[0], p[1], p[2]};
      if (c == scene.floor_color)
        ++floor;
      else if (c == scene.background)
        ++sky;
      else
        ADD_FAILURE() << "pixel " << x << "," << y << " is neither floor nor background";
    }
  EXPECT_GT(floor, w * h / 3);  // camera looks down at 25 degrees: the floor fills the bottom
  EXPECT_EQ(pixel(flat, w, w / 2, h - 1)[0], scene.floor_color[0]);
  // Lit: still only neutral greys (grid, shadowless floor, background fade).
  scene.lit = true;
  r.draw(scene);
  const std::vector<uint8_t> lit = ctx.read_rgba();
  for (size_t i = 0; i < lit.size(); i += 4)
    ASSERT_LE(
        std::max({lit[i], lit[i + 1], lit[i + 2]}) - std::min({lit[i], lit[i + 1], lit[i + 2]}), 12)
        << "coloured pixel in an empty scene at byte " << i;
}

TEST(RenderPixels, SameSceneRenderedTwiceIsByteIdentical) {
  const FrameSet life = take_frame_set(source_of(demo_walker(), Treatment::kStress), {0.3});
  std::vector<const Frame*> frames{&life.frames[0]};
  const ColorScale scale = make_color_scale(ColorMode::kChange, *life.model, frames);
  FrameStyle st = small_style(200, 120);
  st.samples = 4;
  st.overlay = OverlayOptions{};
  std::vector<uint8_t> first;
  {
    FrameRenderer a(st);
    first = a.render(life, life.frames[0], scale, "stress");
  }
  FrameRenderer b(st);
  EXPECT_EQ(b.render(life, life.frames[0], scale, "stress"), first);
  EXPECT_EQ(b.render(life, life.frames[0], scale, "stress"), first);
}

// Edge anti-aliasing (the default): a flat-shaded voxel turned 30 degrees keeps its exact
// colour inside and the floor's outside, and its stair-stepped outline gets pixels mixed
// from the two (each on the line between them); without anti-aliasing there are none.
TEST(RenderPixels, EdgeAntialiasingBlendsOutlinesAndNothingElse) {
  const int w = 160, h = 120;
  const FrameSet life = take_frame_set(source_of(demo_cube(1, 1e8)), {0.0});
  const ColorScale scale = make_color_scale(ColorMode::kCongenital, *life.model, {});
  FrameStyle st = flat_top_view(w, h);
  st.azimuth_deg = -60;
  const Rgb8 voxel = scale.color(*life.model, life.frames[0], 0), floor = Scene{}.floor_color;
  auto mixed_pixels = [&](int samples) {
    st.samples = samples;
    FrameRenderer renderer(st);
    const std::vector<uint8_t> img = renderer.render(life, life.frames[0], scale, "none");
    EXPECT_EQ(Rgb8({pixel(img, w, w / 2, h / 2)[0], pixel(img, w, w / 2, h / 2)[1],
                    pixel(img, w, w / 2, h / 2)[2]}),
              voxel);
    EXPECT_EQ(pixel(img, w, 2, 2)[1], floor[1]);
    int mixed = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint8_t* p = pixel(img, w, x, y);
        const Rgb8 c{p[0], p[1], p[2]};
        if (c == voxel || c == floor) continue;
        ++mixed;
        // On the segment floor -> voxel: one blend fraction explains every channel.
        int best = 0;
        double f = 0;
        for (int d = 0; d < 3; ++d)
          if (std::abs(voxel[d] - floor[d]) > std::abs(voxel[best] - floor[best])) best = d;
        f = (c[best] - floor[best]) / static_cast<double>(voxel[best] - floor[best]);
        EXPECT_GE(f, -0.02);
        EXPECT_LE(f, 1.02);
        for (int d = 0; d < 3; ++d)
          EXPECT_NEAR(c[d], floor[d] + f * (voxel[d] - floor[d]), 2.0)
              << "pixel " << x << "," << y << " channel " << d;
      }
    return mixed;
  };
  EXPECT_EQ(mixed_pixels(1), 0);
  EXPECT_GT(mixed_pixels(kEdgeAntialiasing), 20);
}

// The floor is drawn in pieces (only the one under the robot's shadow with the shadow
// lookup); they meet without cracks: no pixel of the near floor shows the background.
TEST(RenderPixels, FloorPiecesLeaveNoCracks) {
  const int w = 320, h = 240;
  const FrameSet life = take_frame_set(source_of(demo_walker(), Treatment::kNone), {0.0});
  const ColorScale scale = make_color_scale(ColorMode::kCongenital, *life.model, {});
  const Rgb8 background = Scene{}.background;
  for (const int samples : {1, kEdgeAntialiasing, 4}) {
    FrameStyle st = small_style(w, h);
    st.samples = samples;
    for (const double azimuth : {-60.0, 10.0, 135.0}) {
      st.azimuth_deg = azimuth;
      FrameRenderer turned(st);
      const std::vector<uint8_t> img = turned.render(life, life.frames[0], scale, "none");
      int cracks = 0;
      for (int y = h / 2; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const uint8_t* p = pixel(img, w, x, y);
          cracks += p[0] == background[0] && p[1] == background[1] && p[2] == background[2];
        }
      EXPECT_EQ(cracks, 0) << "samples " << samples << ", azimuth " << azimuth;
    }
  }
}

// take_frames hands over exactly the frames take_frame_set keeps, each with the
// settling state the finished life reports (frames before the settle time: not settled).
TEST(RenderLife, StreamedFramesEqualTheCollectedLife) {
  const LifeSource src = source_of(demo_walker(), Treatment::kStress);
  const std::vector<double> times = {0.0, 0.05, 0.1, 0.2, 0.25, 0.3};
  const FrameSet life = take_frame_set(src, times);
  ASSERT_TRUE(life.settled);
  const std::shared_ptr<const Model> model = src.model;
  std::vector<SourcedFrame> streamed;
  take_frames(src, times, [&](SourcedFrame&& f) {
    streamed.push_back(std::move(f));
    return true;
  });
  ASSERT_EQ(streamed.size(), life.frames.size());
  for (size_t k = 0; k < streamed.size(); ++k) {
    const Frame& a = streamed[k].frame;
    const Frame& b = life.frames[k];
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.pos, b.pos);
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.stiffness, b.stiffness);
    const bool before = a.time < model->def.settle_time;
    EXPECT_EQ(streamed[k].settled, !before) << "frame " << k;
    if (!before) {
      EXPECT_EQ(streamed[k].com_settled, life.com_settled);
    }
    FrameSet view;
    view.model = model;
    view.settled = streamed[k].settled;
    view.com_settled = streamed[k].com_settled;
    EXPECT_EQ(displacement_so_far(view, a), displacement_so_far(life, b));
  }
  // Stopping early: the sink's false ends the simulation after that frame.
  int seen = 0;
  take_frames(src, times, [&](SourcedFrame&&) { return ++seen < 2; });
  EXPECT_EQ(seen, 2);
}

// The demo walker's whole life at 10 frames a second, seen with the video's default camera
// path at 16:9: every corner of every voxel, and the floor under every voxel, projects inside
// the image in every frame; the scale is one for the life and the camera glides (its target
// moves less between frames than the body's own bounding-box centre may jump).
TEST(RenderCamera, WalkingRobotStaysInsideTheImageInEveryFrame) {
  const LifeSource src = source_of(demo_walker(), Treatment::kStress);
  std::vector<double> times;
  for (int k = 0; k * 0.1 < src.physics.duration; ++k) times.push_back(k * 0.1);
  const FrameSet life = take_frame_set(src, times);
  ASSERT_EQ(life.frames.size(), times.size());
  std::vector<const Frame*> frames;
  for (const Frame& f : life.frames) frames.push_back(&f);
  const double aspect = 16.0 / 9.0;
  FrameStyle style;
  const std::vector<Camera> cams =
      life_cameras(*life.model, frames, styled_camera(style, Camera{}), aspect);
  ASSERT_EQ(cams.size(), frames.size());
  const Model& m = *life.model;
  double worst = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(cams[k].distance, cams[0].distance);
    const Eigen::Matrix4d vp =
        cams[k].view_projection(aspect, 0.02 * cams[k].distance, 40 * cams[k].distance);
    const Frame& f = *frames[k];
    for (int i = 0; i < m.n; ++i) {
      std::vector<Eigen::Vector3d> points;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d local((c & 1 ? 0.5 : -0.5), (c & 2 ? 0.5 : -0.5),
                                    (c & 4 ? 0.5 : -0.5));
        points.push_back(f.pos[i] + f.orient[i] * (f.size[i] * local));
      }
      points.push_back({f.pos[i].x(), f.pos[i].y(), 0.0});  // the floor under the voxel
      for (const Eigen::Vector3d& p : points) {
        const Eigen::Vector4d q = vp * Eigen::Vector4d(p.x(), p.y(), p.z(), 1);
        ASSERT_GT(q.w(), 0.02 * cams[k].distance) << "frame " << k << " voxel " << i;
        worst = std::max({worst, std::abs(q.x() / q.w()), std::abs(q.y() / q.w())});
      }
    }
  }
  EXPECT_LE(worst, 1.0) << "a voxel leaves the image";
  EXPECT_GT(worst, 0.5) << "the robot should fill a good part of the image";
  // Moving robot, gliding camera: the target travels with the body, in small steps.
  EXPECT_GT((cams.back().target - cams.front().target).head<2>().norm(), 0.005);
  for (size_t k = 1; k < cams.size(); ++k)
    EXPECT_LT((cams[k].target - cams[k - 1].target).norm(), 0.01) << "frame " << k;
}

// A body whose pose leaves follow_camera's view (a tall thin tower seen from close by):
// life_cameras backs off until it fits.
TEST(RenderCamera, LifeCamerasBackOffUntilATallBodyFits) {
  const LifeSource src = source_of(demo_cube(1, 1e8));
  const FrameSet life = take_frame_set(src, {0.0});
  Frame tall = life.frames[0];
  tall.pos[0].z() = 0.2;  // a voxel 20 voxel lengths up
  const std::vector<Camera> cams =
      life_cameras(*life.model, {&tall}, styled_camera(FrameStyle{}, Camera{}), 1.0);
  const Eigen::Matrix4d vp = cams[0].view_projection(1.0, 0.01, 100);
  for (const double z : {0.0, 0.2}) {
    const Eigen::Vector4d q = vp * Eigen::Vector4d(tall.pos[0].x(), tall.pos[0].y(), z, 1);
    EXPECT_LE(std::abs(q.y() / q.w()), 1.0) << z;
  }
  EXPECT_GT(cams[0].distance, follow_camera(*life.model, tall).distance * 3);
}

// ---------------------------------------------------------------------------------------
// Files: frames, videos, galleries, bad input
// ---------------------------------------------------------------------------------------

class RenderFiles : public ScratchDirTest {
 protected:
  // A tiny evolution run (4x4x4 lattice, population 4, 1 generation, 0.3 s lives).
  std::string tiny_run(const std::string& name, uint64_t seed, const std::string& treatment) {
    const std::string json = R"({"format": "plastivox-evolve-config", "version": 1, "seed": )" +
                             std::to_string(seed) + R"(, "treatment": ")" + treatment +
                             R"(", "population": 4, "generations": 1, "threads": 1,
        "lattice": {"nx": 4, "ny": 4, "nz": 4, "voxel_size": 0.01},
        "physics": {"preset": "gecco2018-code", "duration": 0.3, "settle_time": 0.1}})";
    const evo::EvolveConfig config = evo::parse_config(json, name);
    const std::string out = path(name);
    evo::RunOptions opt;
    opt.threads = 1;
    evo::run_evolution(config, out, opt);
    return out;
  }
};

TEST_F(RenderFiles, FrameFromARobotFileIsAPngOfTheRequestedSize) {
  write_robot_file(path("cube.json"), demo_cube(3, 1e7));
  FrameStyle st = small_style(96, 64);
  render_frame_file(path("cube.json"), 0.1, st, path("f.png"));
  const Image img = read_png(path("f.png"));
  EXPECT_EQ(img.width, 96);
  EXPECT_EQ(img.height, 64);
  EXPECT_EQ(files_in(dir_), 2);  // cube.json and f.png, no temporaries
}

TEST_F(RenderFiles, BadInputIsAClearErrorAndLeavesNoFile) {
  write_robot_file(path("cube.json"), demo_cube(2, 1e7));
  FrameStyle st = small_style(32, 32);
  EXPECT_THROW(render_frame_file(path("cube.json"), 0.1, st, path("missing/f.png")), RenderError);
  EXPECT_THROW(render_frame_file(path("cube.json"), 99, st, path("late.png")), RenderError);
  EXPECT_THROW(render_frame_file(path("nothing.json"), 0.1, st, path("f.png")), std::runtime_error);
  EXPECT_THROW(render_frame_file(path("cube.txt"), 0.1, st, path("f.png")), std::runtime_error);
  // A results file whose run has no generation yet (hence no champion) is refused by the
  // results reader, naming the file and the field.
  evo::RunState empty;
  empty.config = evo::parse_config(R"({"format": "plastivox-evolve-config", "version": 1})", "e");
  evo::write_results(path("empty.h5"), empty, current_provenance(1));
  try {
    render_frame_file(path("empty.h5"), 0.1, st, path("f.png"));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("empty.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("generations_done"), std::string::npos) << e.what();
  }
  EXPECT_EQ(files_in(dir_), 2);  // only the inputs
}

TEST_F(RenderFiles, VideoDecodesWithTheExpectedFramesSizeAndDuration) {
  write_robot_file(path("cube.json"), demo_cube(2, 1e7));
  FrameStyle st = small_style(64, 48);
  VideoJob job;
  job.fps = 30;
  job.end = 0.2;  // 6 frames
  const VideoSummary s = render_video_file(path("cube.json"), st, job, path("v.mp4"));
  EXPECT_EQ(s.frames, 6);
  const VideoInfo info = probe_video(path("v.mp4"));
  EXPECT_EQ(info.frames, 6);
  EXPECT_EQ(info.width, 64);
  EXPECT_EQ(info.height, 48);
  EXPECT_NEAR(info.duration_s, 0.2, 0.034);
  EXPECT_EQ(files_in(dir_), 2);
}

// Simulation, drawing and encoding run on three threads; the bytes are the same every
// time, with the default style (edge anti-aliasing, shadows, overlay) and for the colour
// mode that simulates first.
TEST_F(RenderFiles, VideoBytesAreTheSameEveryRun) {
  write_robot_file(path("walker.json"), demo_walker());
  FrameStyle st;
  st.width = 160;
  st.height = 96;
  VideoJob job;
  job.end = 0.4;  // 12 frames, settling included
  auto bytes = [&](const std::string& name) {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const ColorMode mode : {ColorMode::kCongenital, ColorMode::kChange}) {
    st.color = mode;
    EXPECT_EQ(render_video_file(path("walker.json"), st, job, path("a.mp4")).frames, 12);
    render_video_file(path("walker.json"), st, job, path("b.mp4"));
    EXPECT_TRUE(bytes("a.mp4") == bytes("b.mp4")) << to_string(mode);
    EXPECT_GT(bytes("a.mp4").size(), 1000u);
  }
  EXPECT_EQ(files_in(dir_), 3);
}

// A simulation that goes unstable part way (a random 1000-voxel body under the stress
// treatment, at ~0.25 s) stops the three-thread video with the simulation's error, after
// the earlier frames were drawn, and leaves no file.
TEST_F(RenderFiles, UnstableSimulationStopsTheVideoAndLeavesNothing) {
  // A speed limit the walker passes at t = 0.15 s (a few frames in): an instability that does
  // not depend on the details of a chaotic life.
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = Treatment::kStress;
  physics.max_speed = 0.5;
  write_robot_file(path("unstable.json"), demo_walker(), &physics);
  FrameStyle st = small_style(64, 48);
  VideoJob job;
  job.end = 1.0;
  try {
    render_video_file(path("unstable.json"), st, job, path("v.mp4"));
    FAIL() << "expected an error";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("went unstable"), std::string::npos) << e.what();
  }
  EXPECT_EQ(files_in(dir_), 1);  // only the input
}

TEST_F(RenderFiles, GalleryHasOneLabelledTilePerInputEachShowingItsRobot) {
  const std::vector<std::string> runs = {tiny_run("a.h5", 1, "none"), tiny_run("b.h5", 2, "stress"),
                                         tiny_run("c.h5", 3, "pressure")};
  GalleryStyle gs;
  gs.width = 330;
  gs.height = 120;
  gs.samples = 1;
  const GalleryLayout layout = render_gallery_file(runs, gs, path("g.png"));
  ASSERT_EQ(layout.tiles.size(), runs.size());
  EXPECT_EQ(layout.columns * layout.rows >= 3, true);
  EXPECT_EQ(layout.labels[1], "stress · seed 2");
  // Each tile's fitness (its label's second part) is its champion's, as evolution scored it.
  ASSERT_EQ(layout.fitness.size(), runs.size());
  for (size_t k = 0; k < runs.size(); ++k) {
    const evo::ResultsFile results = evo::read_results(runs[k]);
    const double scored = evo::champion_at(results.state, -1, runs[k]).fitness;
    EXPECT_NEAR(layout.fitness[k], scored, 1e-9 * (1 + std::abs(scored))) << runs[k];
  }
  const Image img = read_png(path("g.png"));
  // Labels: ink (dark grey text) in the bottom third of every tile, much more than there is
  // without labels (where the robot, in saturated colours, and its shadow may reach).
  const auto ink_below = [&](const Image& im, const PixelRect& t) {
    int ink = 0;
    for (int y = t.y + t.height * 2 / 3; y < t.y + t.height; ++y)
      for (int x = t.x + 2; x < t.x + t.width - 2; ++x) {
        const uint8_t* p = pixel(im.rgba, im.width, x, y);
        ink += std::max({p[0], p[1], p[2]}) < 120 &&
               std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) < 24;
      }
    return ink;
  };
  gs.labels = false;
  render_gallery_file(runs, gs, path("plain.png"));
  const Image plain = read_png(path("plain.png"));
  for (const PixelRect& t : layout.tiles)
    EXPECT_GT(ink_below(img, t), ink_below(plain, t) + 20) << "no label at " << t.x << "," << t.y;
  // Every tile shows saturated (robot) pixels; the floor and background are grey.
  for (const PixelRect& t : layout.tiles) {
    int coloured = 0;
    for (int y = t.y; y < t.y + t.height; ++y)
      for (int x = t.x; x < t.x + t.width; ++x) {
        const uint8_t* p = pixel(img.rgba, img.width, x, y);
        coloured += std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 40;
      }
    EXPECT_GT(coloured, 20) << "tile at " << t.x << "," << t.y;
  }
}

// An explicit stiffness range (a study's, shared by its galleries of every treatment) is
// the one drawn: the tiles of a gallery given its own data range are those of the data-range
// gallery, byte for byte; another range recolours them.
TEST_F(RenderFiles, GalleryDrawsAnExplicitStiffnessRange) {
  const std::vector<std::string> runs = {tiny_run("a.h5", 1, "none"),
                                         tiny_run("b.h5", 2, "stress")};
  GalleryStyle gs;
  gs.width = 240;
  gs.height = 120;
  gs.samples = 1;
  gs.colorbar = false;  // the bar's title names the range; the tiles must not differ
  const GalleryLayout data = render_gallery_file(runs, gs, path("data.png"));
  EXPECT_GT(data.e0_lo, 0);
  EXPECT_GT(data.e0_hi, data.e0_lo);
  gs.e0_lo = data.e0_lo;
  gs.e0_hi = data.e0_hi;
  const GalleryLayout same = render_gallery_file(runs, gs, path("same.png"));
  EXPECT_DOUBLE_EQ(same.e0_lo, data.e0_lo);
  EXPECT_TRUE(read_png(path("same.png")).rgba == read_png(path("data.png")).rgba);
  gs.e0_lo = 1e5;
  gs.e0_hi = 1e11;
  const GalleryLayout wide = render_gallery_file(runs, gs, path("wide.png"));
  EXPECT_DOUBLE_EQ(wide.e0_lo, 1e5);
  EXPECT_NEAR(wide.e0_hi, 1e11, 1e-3);
  EXPECT_FALSE(read_png(path("wide.png")).rgba == read_png(path("data.png")).rgba);
  gs.e0_lo = 1e9;
  gs.e0_hi = 1e8;
  EXPECT_NE(
      error_of([&] { render_gallery_file(runs, gs, path("bad.png")); }).find("0 < low < high"),
      std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(path("bad.png")));
}

// A champion whose life sinks through the floor (a run evolved under the authors' rule) leaves
// an empty floor in its tile: the tile says SANK, as the study's gallery does; one that
// stands says nothing of the kind.
TEST_F(RenderFiles, GalleryTileOfASunkChampionSaysSo) {
  const std::string sinker =
      std::string(PLASTIVOX_SOURCE_DIR) + "/tests/data/results/old-rule-sinker.h5";
  GalleryStyle gs;
  gs.width = 480;
  gs.height = 160;
  gs.samples = 1;
  const GalleryLayout g =
      render_gallery_file({sinker, tiny_run("a.h5", 1, "none")}, gs, path("g.png"));
  ASSERT_EQ(g.labels.size(), 2u);
  EXPECT_NE(g.labels[0].find(" · SANK"), std::string::npos) << g.labels[0];
  EXPECT_EQ(g.labels[1].find("SANK"), std::string::npos) << g.labels[1];
}

}  // namespace
}  // namespace plastivox::render
