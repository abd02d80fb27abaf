// Recorded lives (issue 16): the plastivox-life HDF5 file round-trips every frame and reads
// as h5py users expect (variable-length UTF-8 strings), old fixed-length strings still read,
// the voxcraft-viz history has the structure its player parses, and render/video draw a
// recorded life without simulating it, pixel for pixel as the simulated one.
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/file_seal.hpp"
#include "plastivox/io/h5_util.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/history_file.hpp"
#include "plastivox/render/render_life.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

// A 3x3x2 block under the code preset with actuation and stress development, 0.3 s.
struct Lived {
  RobotDef robot;
  PhysicsDef physics;
  Model model;
  SimResult result;
};
Lived live(double fps, bool control = false) {
  Lived l;
  l.robot = testing::block(3, 3, 2, 1e9);  // above the development gate
  for (size_t s = 0; s < l.robot.phase.size(); ++s) {
    l.robot.phase[s] = 0.1 * (s % 3);
    l.robot.dev_rate[s] = s % 2 ? 10.0 : -10.0;  // 1/s, as the demo robots' range
  }
  l.physics = preset_gecco2018_code();
  l.physics.treatment = Treatment::kStress;
  l.physics.duration = 0.3;
  l.physics.settle_time = 0.1;
  l.model = compile(l.robot, l.physics);
  SimOptions options;
  options.record_fps = fps;
  options.record_control = control;
  l.result = simulate(l.model, options);
  return l;
}

// The "contact" dataset of the 18-voxel block's life file at `file`; dims gets its shape.
std::vector<uint8_t> read_contact(const std::string& file, std::vector<hsize_t>& dims) {
  const h5::Ctx c{file, 0};
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  dims = {h5::kAnyExtent, 18};
  std::vector<uint8_t> contact = h5::read<uint8_t>(c, f, "contact", dims);
  H5Fclose(f);
  return contact;
}

RecordedLife recorded(const Lived& l) {
  RecordedLife life;
  life.source = "inline block";
  life.robot = l.robot;
  life.physics = l.physics;
  life.result = l.result;
  return life;
}

// Type of attribute `name` on the root of `file`: variable-length? and character set.
struct StringType {
  bool variable = false;
  H5T_cset_t cset = H5T_CSET_ERROR;
};
StringType attr_type(const std::string& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t a = H5Aopen(f, name.c_str(), H5P_DEFAULT);
  const hid_t t = H5Aget_type(a);
  StringType out{H5Tis_variable_str(t) > 0, H5Tget_cset(t)};
  H5Tclose(t);
  H5Aclose(a);
  H5Fclose(f);
  return out;
}

class RecordedLives : public testing::ScratchDirTest {};

TEST_F(RecordedLives, TheFileHoldsEveryFrameBitForBit) {
  const Lived l = live(50);
  ASSERT_EQ(l.result.status, SimStatus::kFinished);
  ASSERT_EQ(l.result.recording.frames.size(), 16u);  // t = 0, 0.02, ..., 0.28 and the end
  write_life_file(path("life.h5"), recorded(l));
  ASSERT_TRUE(is_life_file(path("life.h5")));
  const RecordedLife back = read_life_file(path("life.h5"));
  EXPECT_EQ(back.source, "inline block");
  EXPECT_EQ(back.result.status, SimStatus::kFinished);
  EXPECT_EQ(back.result.fitness, l.result.fitness);
  EXPECT_EQ(back.result.final_state_hash, l.result.final_state_hash);
  EXPECT_EQ(back.physics.treatment, Treatment::kStress);
  EXPECT_EQ(back.robot.present, l.robot.present);
  EXPECT_EQ(back.robot.phase, l.robot.phase);
  EXPECT_EQ(back.result.recording.fps, 50);
  EXPECT_FALSE(back.provenance.plastivox_version.empty());
  EXPECT_FALSE(back.provenance.date_created.empty());
  EXPECT_FALSE(back.provenance.compiler.empty());
  EXPECT_FALSE(back.provenance.build_type.empty());
  EXPECT_EQ(back.provenance.threads, 1);
  ASSERT_EQ(back.result.recording.frames.size(), l.result.recording.frames.size());
  for (size_t k = 0; k < back.result.recording.frames.size(); ++k) {
    const Frame& a = l.result.recording.frames[k];
    const Frame& b = back.result.recording.frames[k];
    EXPECT_EQ(a.time, b.time);
    ASSERT_EQ(b.pos.size(), 18u);
    for (size_t i = 0; i < a.pos.size(); ++i) {
      EXPECT_EQ(a.pos[i], b.pos[i]);
      EXPECT_EQ(a.orient[i].coeffs(), b.orient[i].coeffs());
      EXPECT_EQ(a.size[i], b.size[i]);
      EXPECT_EQ(a.stiffness[i], b.stiffness[i]);
      EXPECT_EQ(a.stimulus[i], b.stimulus[i]);
    }
  }
  // The stress treatment changed stiffness after settling: the file holds it.
  EXPECT_NE(back.result.recording.frames.back().stiffness,
            back.result.recording.frames.front().stiffness);
  // The robot in the file simulates to the same end state.
  Model again = compile(back.robot, back.physics);
  EXPECT_EQ(simulate(again).final_state_hash, l.result.final_state_hash);
}

// The control channels are recorded only on request, change no bit of the life, and
// round-trip through the file; a default file has none of their datasets.
TEST_F(RecordedLives, ControlChannelsAreOptInAndRoundTrip) {
  const Lived plain = live(50), l = live(50, true);
  EXPECT_EQ(l.result.final_state_hash, plain.result.final_state_hash);
  ASSERT_TRUE(l.result.recording.control);
  const auto& frames = l.result.recording.frames;
  ASSERT_EQ(frames.size(), plain.result.recording.frames.size());
  EXPECT_TRUE(plain.result.recording.frames.back().actuation.empty());
  // The sine moves the signal after settling (0.1 s) and the bottom layer touches.
  EXPECT_EQ(frames.front().actuation, std::vector<double>(18, 0.0));
  EXPECT_NE(frames.back().actuation, frames[frames.size() - 2].actuation);
  double touching = 0;
  for (double t : frames.back().touch) touching += t;
  EXPECT_GT(touching, 0);
  for (size_t k = 0; k < frames.size(); ++k) {
    for (double u : frames[k].actuation) EXPECT_LE(std::abs(u), 1.0 + 1e-15);
    EXPECT_EQ(frames[k].pos, plain.result.recording.frames[k].pos);
  }

  write_life_file(path("plain.h5"), recorded(plain));
  write_life_file(path("control.h5"), recorded(l));
  const RecordedLife back = read_life_file(path("control.h5"));
  EXPECT_TRUE(back.result.recording.control);
  ASSERT_EQ(back.result.recording.frames.size(), frames.size());
  for (size_t k = 0; k < frames.size(); ++k)
    for (const FrameField& f : kControlFrameFields) {
      const double* a = f.values(frames[k]);
      const double* b = f.values(back.result.recording.frames[k]);
      EXPECT_TRUE(std::equal(a, a + 18 * f.width, b)) << f.name << " frame " << k;
    }
  const RecordedLife back_plain = read_life_file(path("plain.h5"));
  EXPECT_FALSE(back_plain.result.recording.control);
  EXPECT_TRUE(back_plain.result.recording.frames.back().touch.empty());
  const hid_t f = H5Fopen(path("plain.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const FrameField& c : kControlFrameFields) EXPECT_LE(H5Lexists(f, c.name, H5P_DEFAULT), 0);
  H5Fclose(f);
  EXPECT_LT(std::filesystem::file_size(path("plain.h5")),
            std::filesystem::file_size(path("control.h5")));
}

TEST_F(RecordedLives, ContactIsTheFloorTestOfEachFrame) {
  const Lived l = live(20);
  write_life_file(path("life.h5"), recorded(l));
  std::vector<hsize_t> dims;
  const std::vector<uint8_t> contact = read_contact(path("life.h5"), dims);
  const auto& frames = l.result.recording.frames;
  ASSERT_EQ(dims[0], frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const std::vector<uint8_t> expected = floor_contact(frames[k], true);
    EXPECT_EQ(std::vector<uint8_t>(contact.begin() + 18 * k, contact.begin() + 18 * (k + 1)),
              expected)
        << "frame " << k;
  }
  // At rest at t = 0 nothing presses into the floor; resting under gravity at the end the
  // bottom layer (9 voxels, z < L) does and the top layer does not.
  int at_start = 0, bottom = 0, top = 0;
  for (int i = 0; i < 18; ++i) {
    at_start += contact[i];
    (frames.back().pos[i].z() < 0.01 ? bottom : top) += contact[18 * (frames.size() - 1) + i];
  }
  EXPECT_EQ(at_start, 0);
  EXPECT_GT(bottom, 0);
  EXPECT_EQ(top, 0);
}

// On a ground below z = 0 the recorded contact is the ground's test, not the floor's: a block
// that fell onto a level ground 2 voxel lengths down touches it with its bottom layer only
// (the floor's test would flag both layers, all below z = 0).
TEST_F(RecordedLives, ContactOnAGroundIsTheGroundsTest) {
  Lived l;
  l.robot = testing::block(3, 3, 2, 1e9);
  l.physics = preset_gecco2018_code();
  l.physics.duration = 0.3;
  l.physics.environment.ground.kind = GroundKind::kFlat;
  l.physics.environment.ground.height = -0.02;
  l.model = compile(l.robot, l.physics);
  SimOptions options;
  options.record_fps = 20;
  l.result = simulate(l.model, options);
  ASSERT_EQ(l.result.status, SimStatus::kFinished) << l.result.failure;
  write_life_file(path("ground.h5"), recorded(l));
  std::vector<hsize_t> dims;
  const std::vector<uint8_t> contact = read_contact(path("ground.h5"), dims);
  const Frame& last = l.result.recording.frames.back();
  const size_t at = 18 * (l.result.recording.frames.size() - 1);
  int bottom = 0, top = 0, below_zero = 0;
  for (int i = 0; i < 18; ++i) {
    (last.pos[i].z() < -0.01 ? bottom : top) += contact[at + i];
    below_zero += floor_contact(last, true)[i];
  }
  EXPECT_EQ(below_zero, 18);  // the plain floor test would call every voxel touching
  EXPECT_GT(bottom, 0);
  EXPECT_EQ(top, 0);
}

TEST_F(RecordedLives, StringsAreVariableLengthUtf8AndOldFixedOnesStillRead) {
  const Lived l = live(10);
  write_life_file(path("life.h5"), recorded(l));
  for (const char* name : {"treatment", "format", "robot", "source"}) {
    const StringType t = attr_type(path("life.h5"), name);
    EXPECT_TRUE(t.variable) << name;
    EXPECT_EQ(t.cset, H5T_CSET_UTF8) << name;
  }
  // Datasets of strings, and a non-ASCII value, through the shared writer and reader.
  const h5::Ctx c{path("s.h5"), 0};
  std::string image;
  {
    h5::MemoryFile mf(c, 0);
    h5::write_strings(c, mf.id(), "names", {"stress", "Γ body", ""});
    h5::write_attr(c, mf.id(), "label", std::string("E₀ · 10⁶ Pa"));
    image = mf.image();
  }
  write_file_atomic(path("s.h5"), image);
  const hid_t f = H5Fopen(path("s.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "names", H5P_DEFAULT);
  const hid_t t = H5Dget_type(d);
  EXPECT_GT(H5Tis_variable_str(t), 0);
  EXPECT_EQ(H5Tget_cset(t), H5T_CSET_UTF8);
  H5Tclose(t);
  H5Dclose(d);
  EXPECT_EQ(h5::read_strings(c, f, "names", 3), (std::vector<std::string>{"stress", "Γ body", ""}));
  EXPECT_EQ(h5::read_attr_string(c, f, "/", "label"), "E₀ · 10⁶ Pa");
  H5Fclose(f);

  // A file as this project wrote them before: fixed-length, NUL-terminated ASCII.
  const hid_t old = H5Fcreate(path("old.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t st = H5Tcopy(H5T_C_S1);
  H5Tset_size(st, 7);
  H5Tset_strpad(st, H5T_STR_NULLTERM);
  const hid_t scalar = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(old, "treatment", st, scalar, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, st, "stress");
  H5Aclose(a);
  const hsize_t two = 2;
  const hid_t sp = H5Screate_simple(1, &two, nullptr);
  const hid_t ds = H5Dcreate2(old, "names", st, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const char fixed[14] = "none\0\0\0press";
  H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, fixed);
  H5Dclose(ds);
  H5Sclose(sp);
  H5Sclose(scalar);
  H5Tclose(st);
  H5Fclose(old);
  const h5::Ctx oc{path("old.h5"), 0};
  const hid_t o = H5Fopen(path("old.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_EQ(h5::read_attr_string(oc, o, "/", "treatment"), "stress");
  EXPECT_EQ(h5::read_strings(oc, o, "names", 2), (std::vector<std::string>{"none", "press"}));
  H5Fclose(o);
}

TEST_F(RecordedLives, OldFilesWithFourProvenanceFieldsStillRead) {
  write_life_file(path("life.h5"), recorded(live(10)));
  // Lives written before 2026-12-05 held plastivox_version, git_commit, date_created and host.
  const hid_t f = H5Fopen(path("life.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* name :
       {"compiler", "compiler_flags", "build_type", "date_updated", "threads", "wall_seconds"})
    EXPECT_GE(H5Adelete(f, name), 0) << name;
  H5Fclose(f);
  std::string bytes = read_file_bytes(path("life.h5"));
  seal::seal_image(bytes, path("life.h5"), seal::kLife);
  write_file_atomic(path("life.h5"), bytes);
  const RecordedLife back = read_life_file(path("life.h5"));
  EXPECT_FALSE(back.provenance.plastivox_version.empty());
  EXPECT_FALSE(back.provenance.git_commit.empty());
  EXPECT_FALSE(back.provenance.date_created.empty());
  EXPECT_FALSE(back.provenance.host.empty());
  EXPECT_EQ(back.provenance.compiler, "");
  EXPECT_EQ(back.provenance.date_updated, "");
  EXPECT_EQ(back.provenance.threads, 0);
  EXPECT_EQ(back.provenance.wall_seconds, 0);
}

TEST_F(RecordedLives, ForeignAndBrokenFilesAreRefusedInOneLine) {
  write_file_atomic(path("x.h5"), "not hdf5");
  EXPECT_FALSE(is_life_file(path("x.h5")));
  EXPECT_FALSE(is_life_file(path("missing.h5")));
  // A results file starts with its seal, which is checked before HDF5 reads anything: the
  // test for a recorded life does not hand it to HDF5 either.
  write_file_atomic(path("r.h5"), "plastivox-evolution-results\nseal_version 1\n");
  EXPECT_FALSE(is_life_file(path("r.h5")));
  // ... and read as one, it is named as what it is.
  const std::string r = testing::error_of([&] { read_life_file(path("r.h5")); });
  EXPECT_NE(r.find("r.h5: an evolution results file, not a recorded life"), std::string::npos) << r;
  const std::string e = testing::error_of([&] { read_life_file(path("x.h5")); });
  EXPECT_NE(e.find("x.h5: not an HDF5 file"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // A life that neither finished nor went unstable is not a recorded life's summary.
  RecordedLife running = recorded(live(10));
  running.result.status = SimStatus::kRunning;
  write_life_file(path("running.h5"), running);
  const std::string s = testing::error_of([&] { read_life_file(path("running.h5")); });
  EXPECT_NE(s.find("running.h5: /@status: expected \"finished\" or \"unstable\""),
            std::string::npos)
      << s;
}

// Splits s at every `sep`.
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(part);
  return out;
}

TEST_F(RecordedLives, TheHistoryHasTheStructureVoxcraftVizParses) {
  const Lived l = live(25);
  const std::string text = render::history_text(l.model, l.result.recording);
  const std::vector<std::string> lines = split(text, '\n');
  int settings = 0, colours = 0;
  std::vector<std::string> frames;
  for (const std::string& line : lines) {
    if (line.rfind("{{{setting}}}", 0) == 0) {
      ++settings;
      colours += line.find("<matcolor><id>") != std::string::npos;
    } else {
      frames.push_back(line);
    }
  }
  EXPECT_EQ(lines[0], "{{{setting}}}<rescale>0.001</rescale>");
  EXPECT_EQ(lines[1], "{{{setting}}}<voxel_size>0.01</voxel_size>");
  EXPECT_EQ(colours, render::kHistoryClasses);
  EXPECT_EQ(settings, 2 + render::kHistoryClasses);
  ASSERT_EQ(frames.size(), l.result.recording.frames.size());
  EXPECT_EQ(l.result.recording.frames[0].step, 0);
  double lowest = 1e9;  // the first frame's lowest voxel centre, m, voxcraft's frame
  for (size_t k = 0; k < frames.size(); ++k) {
    const std::string& line = frames[k];
    const Frame& f = l.result.recording.frames[k];
    // "<<<Step<steps> Time:<t>>>>" ... "<<<>>>", as the player cuts it; the step is the
    // simulation's step count (as voxcraft-sim writes it), not the frame index.
    const size_t head = line.find(">>>");
    ASSERT_EQ(line.rfind("<<<Step" + std::to_string(f.step) + " Time:", 0), 0u)
        << line.substr(0, 40);
    if (k > 0) {
      EXPECT_GT(f.step, l.result.recording.frames[k - 1].step);
    }
    EXPECT_NEAR(std::stod(line.substr(line.find("Time:") + 5, head)), f.time, 1e-6);
    ASSERT_EQ(line.substr(line.size() - 7), ";<<<>>>");
    const std::string body = line.substr(head + 3, line.size() - head - 10);  // the player's cut
    const std::vector<std::string> voxels = split(body, ';');
    ASSERT_EQ(voxels.size(), static_cast<size_t>(l.model.n));
    for (int i = 0; i < l.model.n; ++i) {
      const std::vector<std::string> v = split(voxels[i], ',');
      ASSERT_EQ(v.size(), 15u) << voxels[i];  // the player needs at least 15
      // Centre in mm (rescale 0.001) to 0.1 um, in voxcraft's frame: z lowered by L/2.
      for (int a = 0; a < 2; ++a) EXPECT_NEAR(std::stod(v[a]) / 1000, f.pos[i][a], 1e-7);
      EXPECT_NEAR(std::stod(v[2]) / 1000, f.pos[i].z() - 0.5 * l.model.size, 1e-7);
      if (k == 0) lowest = std::min(lowest, std::stod(v[2]) / 1000);
      // Angle and axis give back the orientation.
      const Eigen::Vector3d axis(std::stod(v[4]), std::stod(v[5]), std::stod(v[6]));
      const Eigen::Quaterniond q(
          Eigen::AngleAxisd(std::stod(v[3]) * M_PI / 180, axis.normalized()));
      EXPECT_LT(q.angularDistance(f.orient[i]), 1e-4);
      // Corners: +-half the actuated size, in mm.
      EXPECT_NEAR(std::stod(v[7]), -500 * f.size[i], 1e-4);
      EXPECT_NEAR(std::stod(v[12]), 500 * f.size[i], 1e-4);
      const int material = std::stoi(v[13]);
      EXPECT_GE(material, 1);
      EXPECT_LE(material, render::kHistoryClasses);
      const double signal = std::stod(v[14]);
      EXPECT_GE(signal, 0);
      EXPECT_LE(signal, 100);
    }
  }
  // voxcraft-viz draws its floor at -voxel_size/2: the bottom layer's centres start at z = 0.
  EXPECT_NEAR(lowest, 0.0, 1e-7);
  render::write_history_file(path("life.history"), l.model, l.result.recording);
  EXPECT_EQ(testing::file_text(path("life.history")), text);
}

TEST_F(RecordedLives, ARecordedFrameDrawsAsTheSimulatedOne) {
  const Lived l = live(20);
  write_life_file(path("life.h5"), recorded(l));
  write_robot_file(path("block.json"), l.robot, &l.physics);
  const render::LifeSource from_file = render::load_life_source(path("life.h5"));
  ASSERT_TRUE(from_file.recorded);
  const render::LifeSource simulated = render::load_life_source(path("block.json"));
  ASSERT_FALSE(simulated.recorded);
  render::FrameStyle st;
  st.width = 96;
  st.height = 64;
  st.samples = 1;
  st.color = render::ColorMode::kStiffness;
  for (double t : {0.0, 5 / 20.0}) {  // before settling and after (the frame at t = 0.25 s)
    EXPECT_EQ(render::render_frame(from_file, t, st), render::render_frame(simulated, t, st))
        << "t = " << t;
  }
  EXPECT_NE(testing::error_of([&] {
              render::take_frame_set(from_file, {1.0});
            }).find("past the recording's last frame"),
            std::string::npos);
}

// Colouring by actuation reads the recorded signal: a recorded life with it draws as the
// simulated one, in other pixels than colouring by stiffness; one recorded without it is
// refused in one line saying how to record it. The activity raster shows the same signal.
TEST_F(RecordedLives, ColouringByActuationDrawsTheRecordedSignal) {
  const Lived plain = live(20), l = live(20, true);
  write_life_file(path("plain.h5"), recorded(plain));
  write_life_file(path("control.h5"), recorded(l));
  write_robot_file(path("block.json"), l.robot, &l.physics);
  const render::LifeSource from_file = render::load_life_source(path("control.h5"));
  const render::LifeSource simulated = render::load_life_source(path("block.json"));
  render::FrameStyle st;
  st.width = 96;
  st.height = 64;
  st.samples = 1;
  st.color = render::ColorMode::kActuation;
  const double t = 5 / 20.0;  // after settling: the sine drives the block
  const std::vector<uint8_t> by_actuation = render::render_frame(from_file, t, st);
  EXPECT_EQ(by_actuation, render::render_frame(simulated, t, st));
  st.color = render::ColorMode::kStiffness;
  const std::vector<uint8_t> by_stiffness = render::render_frame(from_file, t, st);
  size_t differing = 0;
  for (size_t k = 0; k < by_actuation.size(); ++k) differing += by_actuation[k] != by_stiffness[k];
  EXPECT_GT(differing, by_actuation.size() / 50) << differing;
  st.color = render::ColorMode::kActuation;
  const std::string refused = testing::error_of(
      [&] { render::render_frame(render::load_life_source(path("plain.h5")), t, st); });
  EXPECT_NE(refused.find("plain.h5: --color actuation needs the actuation signal"),
            std::string::npos)
      << refused;
  EXPECT_NE(refused.find("--record-control"), std::string::npos) << refused;

  const render::ActivityRaster raster = render::actuation_raster(l.result.recording.frames, 4, 5);
  EXPECT_EQ(raster.height, 4);  // 18 voxels in groups of 5
  EXPECT_EQ(raster.width, 4);   // 7 frames in groups of 2
  // Still while settling (white, the map's middle), driven after it (coloured).
  const auto pixel = [&](int row, int col) {
    const uint8_t* p = &raster.rgba[4 * (row * raster.width + col)];
    return std::vector<int>{p[0], p[1], p[2], p[3]};
  };
  const render::Rgb8 mid = render::Colormap::diverging().at(0.5);
  EXPECT_EQ(pixel(0, 0), (std::vector<int>{mid[0], mid[1], mid[2], 255}));
  EXPECT_NE(pixel(0, 3), pixel(0, 0));
}

// A body whose every voxel swings through +-1, in six phases a sixth of a cycle apart (as the
// 180 voxels of the champion in issue 54 did), recorded at 8 frames a cycle: the activity map
// shows it swinging. One row per voxel, each row reaches both ends of the map; grouped six to a
// row (one voxel of each phase, where a mean is 0 at every instant and drew white), every cell
// is as far from white as the group's RMS signal (0.71).
TEST(ActivityRaster, ABodySwingingAtFullAmplitudeDoesNotLookAtRest) {
  const int voxels = 180, count = 210;
  std::vector<Frame> frames(count);
  for (int k = 0; k < count; ++k) {
    frames[k].time = k / 40.0;
    frames[k].pos.resize(voxels);
    for (int i = 0; i < voxels; ++i)
      frames[k].actuation.push_back(std::sin(2 * M_PI * (5 * frames[k].time + (i % 6) / 6.0)));
  }
  const render::Colormap& map = render::Colormap::diverging();
  const render::Rgb8 rest = map.at(0.5);
  const auto from_rest = [&](const render::ActivityRaster& r, int x, int y) {
    const uint8_t* p = &r.rgba[4 * (static_cast<size_t>(y) * r.width + x)];
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(p[c] - rest[c]));
    return d;
  };
  const auto distance = [&](const render::Rgb8& c) {
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(c[k] - rest[k]));
    return d;
  };
  const int full_swing = std::min(distance(map.at(0)), distance(map.at(1)));
  const render::ActivityRaster each = render::actuation_raster(frames, 400, 480, 2);
  EXPECT_EQ(each.rows, voxels);
  EXPECT_EQ(each.columns, count);
  EXPECT_EQ(each.width, 2 * count);  // 2 x 2 pixels a cell, shown at its own size
  EXPECT_EQ(each.height, 2 * voxels);
  for (int y = 0; y < each.height; ++y) {
    int strongest = 0;
    for (int x = 0; x < each.width; ++x) strongest = std::max(strongest, from_rest(each, x, y));
    EXPECT_GE(strongest, full_swing * 95 / 100) << "row " << y;
  }
  const render::ActivityRaster grouped = render::actuation_raster(frames, 30, 480);
  EXPECT_EQ(grouped.rows, 30);
  EXPECT_EQ(grouped.voxels_per_row, 6);
  const int rms = std::min(distance(map.at(0.5 - 0.5 / std::sqrt(2.0))),
                           distance(map.at(0.5 + 0.5 / std::sqrt(2.0))));
  for (int y = 0; y < grouped.height; ++y)
    for (int x = 0; x < grouped.width; ++x)
      ASSERT_GE(from_rest(grouped, x, y), rms * 9 / 10) << "cell " << x << ", " << y;
}

TEST_F(RecordedLives, TheCommandLineRecordsAndReplays) {
  // A soft (1e7 Pa), heavy cube sinks through the floor: scored, the authors' rule, so its
  // life is recorded like any other.
  PhysicsDef scored;
  scored.sinking_invalid = false;
  write_robot_file(path("cube.json"), demo_cube(2, 1e7), &scored);
  const std::string cube = path("cube.json");
  auto r =
      cli("simulate " + cube + " --duration 0.3 --record " + path("life.h5") + " --fps 10 --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\"format\": \"plastivox-life\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"frames\": 4"), std::string::npos) << r.out;  // 0, .1, .2, end
  EXPECT_EQ(read_life_file(path("life.h5")).result.recording.frames.size(), 4u);
  // A frame rate in --physics alone would record and drop the frames: refused, saying how.
  r = cli("simulate " + cube + " --duration 0.3 --physics '{\"record_fps\": 10}' --json");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("--record life.h5 --fps 10"), std::string::npos) << r.out;
  // ... and with --record it is the frame rate.
  r = cli("simulate " + cube + " --duration 0.3 --physics '{\"record_fps\": 20}' --record " +
          path("l.history"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("recorded 7 frames at 20 fps"), std::string::npos) << r.out;
  EXPECT_EQ(cli("simulate " + cube + " --record " + path("x.txt")).status, 2);
  EXPECT_EQ(cli("simulate " + cube + " --fps 10").status, 2);
  // render and video draw the recorded life without simulating.
  r = cli("render " + path("life.h5") + " --out " + path("f.png") + " --time 0.1 --size 64x48");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("reading the recorded frame"), std::string::npos) << r.out;
  r = cli("video " + path("life.h5") + " --out " + path("v.mp4") + " --size 64x48 --fps 10");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("frames of the recorded life"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;
}

// What an h5py user sees (Debian python3-h5py): str attributes in a results file and a
// recorded life, arrays of the documented shapes; and a file h5py changed is refused with
// the way to copy the data out.
TEST_F(RecordedLives, H5pyReadsStringsAsStrAndUnits) {
  if (testing::shell("/usr/bin/python3 -c 'import h5py' 2>&1").status != 0)
    GTEST_SKIP() << "h5py is not installed (apt-get install -y python3-h5py); not checked";
  write_file_atomic(path("c.json"), R"({"format": "plastivox-evolve-config", "version": 1,
    "seed": 4, "treatment": "stress", "population": 6, "generations": 1,
    "lattice": {"nx": 4, "ny": 4, "nz": 4}, "physics": {"duration": 0.2, "settle_time": 0.1}})");
  auto r = cli("evolve --config " + path("c.json") + " --out " + path("run.h5"));
  ASSERT_EQ(r.status, 0) << r.out;
  r = cli("simulate --treatment stress --duration 0.3 --record " + path("life.h5") + " --fps 10");
  ASSERT_EQ(r.status, 0) << r.out;
  write_file_atomic(path("check.py"), R"(import sys, h5py
run = h5py.File(sys.argv[1], "r")
life = h5py.File(sys.argv[2], "r")
assert run.attrs["treatment"] == "stress", repr(run.attrs["treatment"])
assert isinstance(run.attrs["config"], str)
assert run["individuals/failure_reason"].asstr()[:].dtype == object
assert life.attrs["treatment"] == "stress", repr(life.attrs["treatment"])
assert life.attrs["format"] == "plastivox-life"
n = life.attrs["voxels"]
assert life["position"].shape == (4, n, 3), life["position"].shape
assert life["orientation"].shape == (4, n, 4)
assert life["contact"].shape == (4, n)
units = {(run, "generations/fitness"): "voxel lengths", (run, "individuals/fitness"): "voxel lengths",
         (run, "generations/wall_seconds"): "s", (run, "champion/phenotype/stiffness"): "Pa",
         (run, "champion/phenotype/dev_rate"): "1/s", (run, "champion/phenotype/phase"): "cycles",
         (run, "champion/final_stiffness"): "Pa", (life, "time"): "s", (life, "position"): "m",
         (life, "size"): "m", (life, "stiffness"): "Pa", (life, "stimulus"): "Pa",
         (life, "com_settled"): "m", (life, "orientation"): "1"}
for (f, name), want in units.items():
    assert f[name].attrs["units"] == want, (name, f[name].attrs.get("units"))
print("h5py ok", n)
)");
  const testing::Output py = testing::shell("/usr/bin/python3 " + path("check.py") + " " +
                                            path("run.h5") + " " + path("life.h5") + " 2>&1");
  EXPECT_EQ(py.status, 0) << py.out;
  EXPECT_NE(py.out.find("h5py ok"), std::string::npos) << py.out;
  // Reading left it intact; writing one attribute breaks the seal, and the refusal says how
  // to copy the data out instead.
  EXPECT_EQ(cli("inspect " + path("run.h5")).status, 0);
  const testing::Output edit =
      testing::shell("/usr/bin/python3 -c \"import h5py; f = h5py.File('" + path("run.h5") +
                     "', 'a'); f.attrs['note'] = 'mine'; f.close()\" 2>&1");
  ASSERT_EQ(edit.status, 0) << edit.out;
  r = cli("inspect " + path("run.h5"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("read it with h5py.File(path, 'r') and copy what you need"),
            std::string::npos)
      << r.out;
}

}  // namespace
}  // namespace plastivox
