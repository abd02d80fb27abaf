// Drawing the world beyond the flat floor (docs/rendering.md, "The world"): the ground's mesh
// (render/src/world_mesh.cpp), the pixels of grounds and obstacles in frames, the cameras over
// a ground, the viewer's meta.world and a recorded life that carries its environment to
// `render` and `view`.
#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/render_life.hpp"
#include "plastivox/render/viewer.hpp"
#include "test_support.hpp"

namespace plastivox::render {
namespace {

GroundDef step_at(double at, double height) {
  GroundDef g;
  g.kind = GroundKind::kStep;
  g.at = at;
  g.height = height;
  return g;
}

GroundDef ramp_at(double at, double angle_deg, double length) {
  GroundDef g;
  g.kind = GroundKind::kRamp;
  g.at = at;
  g.angle_deg = angle_deg;
  g.length = length;
  return g;
}

ObstacleBox box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return {{x0, y0, z0}, {x1, y1, z1}};
}

// ---------------------------------------------------------------------------------------
// The mesh
// ---------------------------------------------------------------------------------------

TEST(WorldMesh, GroundBendsAreWhereTheSurfaceBends) {
  // A ramp sampled every millimetre bends at its two ends only.
  const HeightField ramp = make_height_field(ramp_at(0.1, 10, 0.3));
  ASSERT_GT(ramp.nx, 300);
  const std::vector<double> x = ground_bends(ramp, 0, -1, 1, kMaxGroundLines);
  ASSERT_EQ(x.size(), 2u) << ::testing::PrintToString(x);
  EXPECT_NEAR(x[0], 0.1, 1e-12);
  EXPECT_NEAR(x[1], 0.4, 1e-12);
  EXPECT_TRUE(ground_bends(ramp, 1, -1, 1, kMaxGroundLines).empty());  // constant along y
  // Only lines strictly inside the range asked for.
  EXPECT_EQ(ground_bends(ramp, 0, 0.2, 1, kMaxGroundLines), std::vector<double>{x[1]});
  // Stairs: the foot and the brink of every riser.
  GroundDef stairs;
  stairs.kind = GroundKind::kStairs;
  stairs.rise = 0.01;
  stairs.run = 0.03;
  stairs.count = 3;
  const std::vector<double> s = ground_bends(make_height_field(stairs), 0, -1, 1, kMaxGroundLines);
  ASSERT_EQ(s.size(), 6u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s[2 * k], 0.03 * k, 1e-12);
    EXPECT_NEAR(s[2 * k + 1], 0.03 * k + 0.001, 1e-12);
  }
  // A level ground has none; a rough one bends everywhere and is thinned to the limit.
  GroundDef flat;
  flat.kind = GroundKind::kFlat;
  flat.height = 0.02;
  EXPECT_TRUE(ground_bends(make_height_field(flat), 0, -1, 1, kMaxGroundLines).empty());
  GroundDef rough;
  rough.kind = GroundKind::kRough;
  rough.cell = 0.001;
  rough.nx = 1000;
  rough.ny = 2;
  rough.amplitude = 0.01;
  const std::vector<double> r = ground_bends(make_height_field(rough), 0, -1, 1, 100);
  EXPECT_LE(r.size(), 100u);
  EXPECT_GE(r.size(), 90u);
  EXPECT_TRUE(std::is_sorted(r.begin(), r.end()));
}

// Every corner of the ground's triangles lies on the ground, every normal points up, the
// triangles tile the square once, and those in the shadow rectangle come first; boxes come
// after, split the same way, and a box outside the square is left out.
TEST(WorldMesh, TrianglesLieOnTheGroundAndTileTheSquare) {
  const HeightField f = make_height_field(step_at(0.02, 0.01));
  const std::vector<ObstacleBox> boxes = {box(0.0, 0.0, 0.0, 0.01, 0.01, 0.01),
                                          box(0.08, 0.08, 0.0, 0.09, 0.09, 0.01),
                                          box(0.5, 0.5, 0.0, 0.6, 0.6, 0.1)};
  const Eigen::Vector2d lo(-0.01, -0.01), hi(0.03, 0.02);
  const WorldTriangles t = world_triangles(&f, boxes, Eigen::Vector2d(0, 0), 0.1, lo, hi);
  EXPECT_EQ(t.counts[2], 36);  // the box over the shadow rectangle: 12 triangles
  EXPECT_EQ(t.counts[3], 36);  // the other box in the square; the far one is left out
  const int ground = t.counts[0] + t.counts[1];
  ASSERT_EQ(t.corners.size(), 6u * (ground + 72));
  ASSERT_GT(t.counts[0], 0);
  double area = 0;
  bool riser = false;
  for (int k = 0; k < ground; k += 3) {
    Eigen::Vector3d p[3];
    for (int c = 0; c < 3; ++c) {
      const float* v = &t.corners[6 * (k + c)];
      p[c] = Eigen::Vector3d(v[0], v[1], v[2]);
      EXPECT_NEAR(p[c].z(), f.height(p[c].x(), p[c].y()), 1e-7);
      EXPECT_GT(v[5], 0.0f);  // normal up
      riser = riser || v[3] < -0.9f;
      if (k < t.counts[0]) {  // in the shadow rectangle
        EXPECT_GE(p[c].x(), lo.x() - 1e-7);
        EXPECT_LE(p[c].x(), hi.x() + 1e-7);
        EXPECT_GE(p[c].y(), lo.y() - 1e-7);
        EXPECT_LE(p[c].y(), hi.y() + 1e-7);
      }
    }
    const Eigen::Vector2d a = p[1].head<2>() - p[0].head<2>(), b = p[2].head<2>() - p[0].head<2>();
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  EXPECT_NEAR(area, 0.2 * 0.2, 1e-8);  // corners are floats
  EXPECT_TRUE(riser) << "the step's riser (a slope over one edge) is not in the mesh";
  // A flat ground is the floor's plane: level triangles, normals exactly up.
  GroundDef flat;
  flat.kind = GroundKind::kFlat;
  const HeightField plane = make_height_field(flat);
  const WorldTriangles p = world_triangles(&plane, {}, Eigen::Vector2d(0, 0), 0.1, lo, hi);
  EXPECT_EQ(p.counts[0] + p.counts[1], 9 * 6);  // the floor's 3 x 3 pieces
  for (size_t k = 0; k < p.corners.size(); k += 6) {
    EXPECT_EQ(p.corners[k + 2], 0.0f);
    EXPECT_EQ(p.corners[k + 5], 1.0f);
  }
}

// ---------------------------------------------------------------------------------------
// Pixels
// ---------------------------------------------------------------------------------------

const uint8_t* pixel(const std::vector<uint8_t>& rgba, int width, int x, int y) {
  return rgba.data() + (static_cast<size_t>(y) * width + x) * 4;
}

// Zoomed out: the ground 3 to 4 cm beside the body is in the image.
FrameStyle style(int w, int h) {
  FrameStyle st;
  st.width = w;
  st.height = h;
  st.zoom = 0.5;
  st.samples = 1;
  st.overlay = {false, false, false, false, false};
  return st;
}

// A 3 x 3 x 2 block (x, y in [-0.005, 0.025] m) in `env`, drawn at t = 0 by the camera
// render_frame uses.
struct Shot {
  std::vector<uint8_t> rgba;
  Camera camera;
  std::shared_ptr<const Model> model;
};
Shot shoot(const Environment& env, const FrameStyle& st) {
  PhysicsDef physics = preset_gecco2018_code();
  physics.environment = env;
  const LifeSource src =
      simulated_life_source("inline", testing::block(3, 3, 2, 1e7), physics, "block");
  const FrameSet life = take_frame_set(src, {0.0});
  const ColorScale scale = make_color_scale(ColorMode::kCongenital, *life.model, {});
  const Camera cam = life_cameras(*life.model, {&life.frames[0]}, styled_camera(st, Camera{}),
                                  static_cast<double>(st.width) / st.height, st.zoom)[0];
  FrameRenderer renderer(st);
  return {renderer.render(life, life.frames[0], scale, "none", cam), cam, life.model};
}

// The pixel (column, row from the top) where the camera sees world point p.
Eigen::Vector2i project(const Camera& c, const Eigen::Vector3d& p, int w, int h) {
  const Eigen::Vector4d q = c.view_projection(static_cast<double>(w) / h, 1e-3, 1e3) *
                            Eigen::Vector4d(p.x(), p.y(), p.z(), 1);
  return {static_cast<int>((q.x() / q.w() + 1) / 2 * w),
          static_cast<int>((1 - q.y() / q.w()) / 2 * h)};
}

// Mean of the three channels over the 5 x 5 pixels around (x, y).
double brightness(const std::vector<uint8_t>& rgba, int w, const Eigen::Vector2i& at) {
  double sum = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const uint8_t* p = pixel(rgba, w, at.x() + dx, at.y() + dy);
      sum += p[0] + p[1] + p[2];
    }
  return sum / 75;
}

// Lit, a step's riser facing the camera and a ramp falling away from the light are darker
// than the floor there; beside them, on the level ground before the step, the pixels are
// the floor's to within a level of rounding.
TEST(RenderWorld, AStepAndARampChangeThePixelsOverTheTerrain) {
  const int w = 200, h = 150;
  FrameStyle st = style(w, h);
  st.shadows = false;
  st.azimuth_deg = -120;  // from -x: the riser of a step up along +x faces the camera
  Environment step;
  step.ground = step_at(0.04, 0.01);
  const Shot flat = shoot({}, st), stepped = shoot(step, st);
  ASSERT_EQ(flat.camera.target, stepped.camera.target);  // the ground under the body is level
  const Eigen::Vector2i riser = project(flat.camera, {0.0405, 0.01, 0.005}, w, h);
  ASSERT_TRUE(riser.x() > 2 && riser.x() < w - 3 && riser.y() > 2 && riser.y() < h - 3);
  EXPECT_LT(brightness(stepped.rgba, w, riser), brightness(flat.rgba, w, riser) - 10);
  // Level ground before the step, clear of the body: the floor's look.
  int compared = 0;
  for (const double y : {-0.03, -0.02, 0.04, 0.05}) {
    const Eigen::Vector2i at = project(flat.camera, {0.0, y, 0.0}, w, h);
    if (at.x() < 0 || at.x() >= w || at.y() < 0 || at.y() >= h) continue;
    ++compared;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(pixel(stepped.rgba, w, at.x(), at.y())[c], pixel(flat.rgba, w, at.x(), at.y())[c],
                  1)
          << "y " << y;
  }
  EXPECT_GE(compared, 2);

  st.azimuth_deg = -60;  // from +x, the light from -x: a ramp down along +x faces away
  Environment ramp;
  ramp.ground = ramp_at(0.04, -30, 0.1);
  const Shot flat2 = shoot({}, st), ramped = shoot(ramp, st);
  const double x = 0.06;
  const Eigen::Vector2i on_ramp =
      project(ramped.camera, {x, 0.01, ramped.model->ground.height(x, 0.01)}, w, h);
  ASSERT_TRUE(on_ramp.x() > 2 && on_ramp.x() < w - 3 && on_ramp.y() > 2 && on_ramp.y() < h - 3);
  EXPECT_LT(brightness(ramped.rgba, w, on_ramp), brightness(flat2.rgba, w, on_ramp) - 8);
}

// Seen from straight above with flat colours, an obstacle's top is exactly the obstacle
// colour where it projects, the floor's colour without it; a flat ground above the floor
// (the body stands on it) keeps the floor's colour.
TEST(RenderWorld, ObstaclesAppearInTheirColourWhereTheyProject) {
  const int w = 160, h = 120;
  FrameStyle st = style(w, h);
  st.orthographic = true;
  st.elevation_deg = 90;
  st.lit = false;
  Environment env;
  env.obstacles = {box(0.03, -0.02, 0.0, 0.05, 0.0, 0.02)};
  const Shot with = shoot(env, st), without = shoot({}, st);
  const Eigen::Vector2i top = project(with.camera, {0.04, -0.01, 0.02}, w, h);
  ASSERT_TRUE(top.x() >= 0 && top.x() < w && top.y() >= 0 && top.y() < h);
  const Rgb8 stone = Scene{}.obstacle_color, floor = Scene{}.floor_color;
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(pixel(with.rgba, w, top.x(), top.y())[c], stone[c]);
    EXPECT_EQ(pixel(without.rgba, w, top.x(), top.y())[c], floor[c]);
  }
  int stone_pixels = 0;
  for (size_t i = 0; i < with.rgba.size(); i += 4)
    stone_pixels += Rgb8{with.rgba[i], with.rgba[i + 1], with.rgba[i + 2]} == stone;
  EXPECT_GT(stone_pixels, 50);
  Environment raised;
  raised.ground.kind = GroundKind::kFlat;
  raised.ground.height = -0.01;
  const Shot level = shoot(raised, st);
  const Eigen::Vector2i beside = project(level.camera, {0.05, -0.02, -0.01}, w, h);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(pixel(level.rgba, w, beside.x(), beside.y())[c], floor[c]);
}

// A flat ground at z = 0 is simulated as the floor (the same bits) and drawn through the
// world's mesh: it looks like the floor, lit and shadowed, to within rounding.
TEST(RenderWorld, AFlatGroundAtZeroLooksLikeTheFloor) {
  const int w = 200, h = 150;
  Environment env;
  env.ground.kind = GroundKind::kFlat;
  const Shot ground = shoot(env, style(w, h)), floor = shoot({}, style(w, h));
  int off = 0;
  for (size_t i = 0; i < floor.rgba.size(); ++i) {
    EXPECT_LE(std::abs(ground.rgba[i] - floor.rgba[i]), 2) << "byte " << i;
    off += ground.rgba[i] != floor.rgba[i];
  }
  EXPECT_LT(off, static_cast<int>(floor.rgba.size() / 100));
}

// ---------------------------------------------------------------------------------------
// Cameras
// ---------------------------------------------------------------------------------------

// The follow camera looks at the body's middle above the ground under it; the life camera
// keeps the ground under the body in the image, so a ground far below lowers its target.
TEST(RenderWorld, CamerasFrameTheBodyAndTheGroundUnderIt) {
  Environment low;
  low.ground.kind = GroundKind::kFlat;
  low.ground.height = -0.05;
  PhysicsDef physics = preset_gecco2018_code();
  const Model flat = compile(testing::block(3, 3, 2, 1e7), physics);
  physics.environment = low;
  const Model lowered = compile(testing::block(3, 3, 2, 1e7), physics);
  Frame f;
  for (int i = 0; i < flat.n; ++i) {
    f.pos.push_back(flat.rest_pos[i]);
    f.orient.push_back(Eigen::Quaterniond::Identity());
    f.size.push_back(flat.size);
  }
  const Camera a = follow_camera(flat, f), b = follow_camera(lowered, f);
  EXPECT_DOUBLE_EQ(a.target.z(), 0.01);  // half the 2-voxel height
  EXPECT_DOUBLE_EQ(b.target.z(), -0.05 + 0.01);
  const Camera la = life_cameras(flat, {&f}, Camera{}, 1.5)[0];
  const Camera lb = life_cameras(lowered, {&f}, Camera{}, 1.5)[0];
  EXPECT_LT(lb.target.z(), la.target.z() - 0.02);
  EXPECT_GT(lb.distance, la.distance);
  EXPECT_DOUBLE_EQ(lb.target.x(), la.target.x());  // still centred on the body
}

// ---------------------------------------------------------------------------------------
// The viewer and recorded lives
// ---------------------------------------------------------------------------------------

// meta.world: the ground's bends and heights and the boxes for a life in an environment;
// nothing for a life on the floor (its page is as before).
TEST(ViewerWorld, MetaCarriesTheGroundAndBoxesOnlyBeyondTheFloor) {
  PhysicsDef physics = preset_gecco2018_code();
  physics.environment.ground = step_at(0.04, 0.01);
  physics.environment.obstacles = {box(0.03, -0.02, 0.0, 0.05, 0.0, 0.02),
                                   box(3.0, 3.0, 0.0, 3.1, 3.1, 0.1)};  // far away
  const Model model = compile(testing::block(3, 3, 2, 1e7), physics);
  const Model plain = compile(testing::block(3, 3, 2, 1e7), preset_gecco2018_code());
  Recording rec;
  Frame f;
  for (int i = 0; i < model.n; ++i) {
    f.pos.push_back(model.rest_pos[i]);
    f.orient.push_back(Eigen::Quaterniond::Identity());
    f.size.push_back(model.size);
    f.stiffness.push_back(1e7);
    f.stimulus.push_back(0);
  }
  rec.frames = {f};
  ViewerItem life;
  life.model = &plain;
  life.recording = &rec;
  EXPECT_FALSE(nlohmann::json::parse(life_meta_json(life)).contains("world"));
  life.model = &model;
  const nlohmann::json world = nlohmann::json::parse(life_meta_json(life)).at("world");
  const auto xs = world.at("ground").at("x").get<std::vector<double>>();
  const auto ys = world.at("ground").at("y").get<std::vector<double>>();
  const auto hs = world.at("ground").at("h").get<std::vector<double>>();
  // The square's two edges and the riser's foot and brink along x; the edges along y.
  ASSERT_EQ(xs.size(), 4u) << ::testing::PrintToString(xs);
  EXPECT_NEAR(xs[1], 0.04, 1e-6);
  EXPECT_NEAR(xs[2], 0.041, 1e-6);
  ASSERT_EQ(ys.size(), 2u);
  ASSERT_EQ(hs.size(), 8u);
  EXPECT_EQ(hs[0], 0.0);
  EXPECT_EQ(hs[3], 0.01);
  EXPECT_NEAR(xs[3] - xs[0], 0.02 + 0.4, 1e-6);  // 20 voxel lengths around the body's 2 cm
  EXPECT_EQ(world.at("obstacles"), nlohmann::json::parse("[[0.03, -0.02, 0.0, 0.05, 0.0, 0.02]]"));
  EXPECT_EQ(world.at("zmin").get<double>(), 0.0);
  EXPECT_NE(viewer_page({life}, "t").find("\"world\":{"), std::string::npos);
}

class WorldFiles : public testing::ScratchDirTest {};

// A life recorded by `simulate --record` keeps its environment: read back it has it, `render`
// draws it as the robot file's simulated life (not as the flat floor), and `view` puts it in
// the page, whose viewer draws the ground and the boxes (headless Chromium, when installed).
TEST_F(WorldFiles, ARecordedLifeCarriesItsEnvironmentToRenderAndView) {
  PhysicsDef physics = preset_gecco2018_code();
  physics.duration = 0.2;
  physics.settle_time = 0.1;
  physics.environment.ground = step_at(0.04, -0.01);
  physics.environment.obstacles = {box(-0.04, -0.02, 0.0, -0.02, 0.0, 0.02)};
  physics.sinking_invalid = false;  // soft and heavy, it sinks a little: scored all the same
  const RobotDef robot = testing::block(3, 3, 2, 1e7);
  write_robot_file(path("env.json"), robot, &physics);
  PhysicsDef plain = physics;
  plain.environment = {};
  write_robot_file(path("plain.json"), robot, &plain);
  const std::string cli = PLASTIVOX_CLI;
  const auto sim = testing::shell(cli + " simulate " + path("env.json") + " --record " +
                                  path("life.h5") + " 2>&1");
  ASSERT_EQ(sim.status, 0) << sim.out;
  EXPECT_EQ(read_life_file(path("life.h5")).physics.environment, physics.environment);

  FrameStyle st = style(120, 90);
  const auto recorded = render_frame(load_life_source(path("life.h5")), 0.1, st);
  EXPECT_EQ(recorded, render_frame(load_life_source(path("env.json")), 0.1, st));
  EXPECT_NE(recorded, render_frame(load_life_source(path("plain.json")), 0.1, st));

  const auto view =
      testing::shell(cli + " view " + path("life.h5") + " --out " + path("page.html") + " 2>&1");
  ASSERT_EQ(view.status, 0) << view.out;
  std::string html = read_file_bytes(path("page.html"));
  EXPECT_NE(html.find("\"obstacles\":[[-0.04,-0.02,0.0,-0.02,0.0,0.02]]"), std::string::npos);
  EXPECT_NE(html.find("\"zmin\":-0.01"), std::string::npos);

  const std::string chromium = testing::headless_chromium(path("profile"));
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium); page not opened";
  const std::string probe = R"(<script>
(function () {
  const v = plastivoxViewer.viewer;
  const kinds = v.worldParts.map((p) => p.type + ":" + p.geometry.attributes.position.count);
  document.body.setAttribute("data-world", JSON.stringify({ parts: kinds, floor: v.floorZ }));
})();
</script>)";
  html.insert(html.rfind("</body>"), probe);
  write_file_atomic(path("check.html"), html);
  const auto dom =
      testing::shell(chromium + "--window-size=1000,900 --enable-logging=stderr " +
                     "--v=0 --dump-dom file://" + path("check.html") + " 2>" + path("console.log"));
  ASSERT_EQ(dom.status, 0);
  const std::string console = read_file_bytes(path("console.log"));
  for (const char* bad : {"Uncaught", "ERR_", "WebGL: "})
    EXPECT_EQ(console.find(bad), std::string::npos) << bad << " in:\n" << console;
  const std::string text = testing::dom_attribute(dom.out, "data-world");
  ASSERT_FALSE(text.empty()) << dom.out;
  const nlohmann::json out = nlohmann::json::parse(text);
  // The ground (3 x 1 cells: the step's riser between two level parts) and one box (36
  // corners), no flat floor or grid; the camera may go down to the step's foot.
  EXPECT_EQ(out.at("parts"), nlohmann::json::parse(R"(["Mesh:18", "Mesh:36"])"));
  EXPECT_EQ(out.at("floor").get<double>(), -0.01);
}

}  // namespace
}  // namespace plastivox::render
