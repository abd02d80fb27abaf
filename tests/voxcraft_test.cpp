// voxcraft-sim's dialect (issue 38): the stiffness palette, export checked tag by tag against
// the rules of voxcraft-sim's own reader (held here: its VXD merge, tag defaults, ASCII
// layers, MathTree evaluation, temperature actuation and time step), import of its demo robots
// (they load, stay stable and stand on the floor), the features refused in one line, and the
// round trip plastivox -> voxcraft -> plastivox.
#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <stack>
#include <string>
#include <utility>
#include <vector>

#include "plastivox/io/voxcraft.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

const std::string kDemos = testing::data_dir() + "/voxcraft/";

// ---- voxcraft-sim's reader rules, as its sources state them ----------------------------

// The element at path[0]/path[1]/... below e, made (with every parent) where missing, as
// ptree's put does.
XMLElement* put(XMLElement* e, const std::vector<std::string>& path, size_t from = 0) {
  if (from == path.size()) return e;
  XMLElement* child = e->FirstChildElement(path[from].c_str());
  return put(child ? child : e->InsertNewChildElement(path[from].c_str()), path, from + 1);
}

// The merge (VX3_SimulationManager::readVXD with ctool::ptree_merge): every child of <VXD>
// carrying replace="VXA.A.B" becomes the element at that path of the base VXA.
void voxcraft_merge(tinyxml2::XMLDocument& base, const tinyxml2::XMLDocument& vxd) {
  ASSERT_STREQ(vxd.RootElement()->Name(), "VXD");
  for (const XMLElement* c = vxd.RootElement()->FirstChildElement(); c;
       c = c->NextSiblingElement()) {
    const char* replace = c->Attribute("replace");
    ASSERT_NE(replace, nullptr) << c->Name() << " would be ignored by voxcraft-sim";
    std::vector<std::string> path;
    std::stringstream ss(replace);
    for (std::string part; std::getline(ss, part, '.');) path.push_back(part);
    ASSERT_GE(path.size(), 2u);
    ASSERT_EQ(path[0], "VXA");
    path.erase(path.begin());
    XMLElement* slot = put(base.RootElement(), path);  // the element the child takes the place of
    XMLElement* copy = c->DeepClone(&base)->ToElement();
    copy->SetName(path.back().c_str());
    XMLNode* parent = slot->Parent();
    parent->InsertAfterChild(slot, copy);
    parent->DeleteChild(slot);
  }
}

// The element at "A/B/C" below e, or null.
const XMLElement* at(const XMLElement* e, const std::string& path) {
  std::stringstream ss(path);
  for (std::string part; e && std::getline(ss, part, '/');) e = e->FirstChildElement(part.c_str());
  return e;
}
double num(const XMLElement* e, const std::string& path) {
  const XMLElement* x = at(e, path);
  EXPECT_NE(x, nullptr) << "missing " << path;
  return x && x->GetText() ? std::atof(x->GetText()) : NAN;
}

// VX3_MathTree as voxcraft-sim builds and evaluates it: the tree's elements in breadth-first
// order pushed on a stack (so popped in reverse), then a queue machine over the tokens.
double mathtree_at_time(const XMLElement* formula, double t) {
  std::vector<std::pair<std::string, std::string>> bfs;
  std::vector<const XMLElement*> frontier = {formula};
  for (size_t k = 0; k < frontier.size(); ++k)
    for (const XMLElement* c = frontier[k]->FirstChildElement(); c; c = c->NextSiblingElement()) {
      bfs.emplace_back(c->Name(), c->GetText() ? c->GetText() : "");
      frontier.push_back(c);
    }
  std::vector<double> values;
  size_t process = 0;
  for (auto it = bfs.rbegin(); it != bfs.rend(); ++it) {
    const std::string& op = it->first;
    double v = 0;
    if (op == "mtCONST") {
      v = std::stod(it->second);
    } else if (op == "mtVAR") {
      EXPECT_EQ(it->second, "t") << "the stop formula reads " << it->second;
      v = t;
    } else {  // binary operators: values[process + 1] OP values[process]
      const double a = values.at(process + 1), b = values.at(process);
      process += 2;
      if (op == "mtSUB")
        v = a - b;
      else if (op == "mtADD")
        v = a + b;
      else if (op == "mtGREATERTHAN")
        v = a > b;
      else
        ADD_FAILURE() << "operator " << op << " not expected in a stop formula";
    }
    values.push_back(v);
  }
  return values.at(process);
}

// The exported pair, merged.
struct Exported {
  VoxcraftFiles files;
  tinyxml2::XMLDocument doc;
  const XMLElement* vxa() const { return doc.RootElement(); }
};
void export_and_merge(const RobotDef& robot, const PhysicsDef& p, Exported& e) {
  e.files = write_voxcraft(robot, p, false);
  tinyxml2::XMLDocument vxd;
  ASSERT_EQ(e.doc.Parse(e.files.base_vxa.c_str()), tinyxml2::XML_SUCCESS);
  ASSERT_EQ(vxd.Parse(e.files.robot_vxd.c_str()), tinyxml2::XML_SUCCESS);
  voxcraft_merge(e.doc, vxd);
}

// A 4x3x2 walker-like body: five stiffness levels, graded phases, default physics.
RobotDef sample_robot() {
  RobotDef r = testing::block(4, 3, 2, 1e8);
  const double levels[] = {3e7, 1e8, 4e8, 2e9, 1e10};
  for (int s = 0; s < r.sites(); ++s) {
    r.stiffness[s] = levels[(s * 7) % 5];
    r.phase[s] = 0.05 * (s % 9) - 0.2;
  }
  r.present[r.site(3, 2, 1)] = 0;  // not a full block
  // The stiffest voxels side by side: voxcraft-sim's dt (stiffest bond) is then plastivox's
  // (stiffest voxel) with the same DtFrac.
  r.stiffness[0] = r.stiffness[1] = 1e10;
  return r;
}

// ---- the palette -----------------------------------------------------------------------

TEST(VoxcraftPalette, FewDistinctValuesAreKeptExactly) {
  const StiffnessPalette p = quantise_stiffness({3e7, 1e5, 3e7, 2.5e9, 1e5}, 78);
  EXPECT_EQ(p.levels, (std::vector<double>{1e5, 3e7, 2.5e9}));
  EXPECT_EQ(p.level_of, (std::vector<int>{1, 0, 1, 2, 0}));
  EXPECT_EQ(p.max_rel_error, 0.0);
}

TEST(VoxcraftPalette, SixDecadesInto78LevelsStayWithinTheCoverBound) {
  // 2000 moduli spread evenly in log over [1e5, 1e11], as the paper's range.
  std::vector<double> e;
  for (int i = 0; i < 2000; ++i) e.push_back(1e5 * std::pow(1e6, i / 1999.0));
  const StiffnessPalette p = quantise_stiffness(e, kVoxcraftMaxMaterials);
  EXPECT_LE(p.levels.size(), 78u);
  for (size_t k = 1; k < p.levels.size(); ++k) EXPECT_LT(p.levels[k - 1], p.levels[k]);
  // Evenly spread values need 78 windows of log-width ln(1e6)/78; each level sits mid-window.
  const double half = std::log(1e6) / 78 / 2;
  EXPECT_LE(p.max_rel_error, std::exp(half) - 1 + 1e-9);
  EXPECT_GT(p.max_rel_error, 0.8 * (std::exp(half) - 1));  // and the bound is nearly reached
  double worst = 0;
  for (size_t i = 0; i < e.size(); ++i)
    worst = std::max(worst, std::abs(p.levels[p.level_of[i]] - e[i]) / e[i]);
  EXPECT_EQ(worst, p.max_rel_error);
}

// ---- export, tag by tag ---------------------------------------------------------------

TEST(VoxcraftExport, FilesReadByVoxcraftSimsRulesGiveTheRobotAndItsPhysics) {
  const RobotDef robot = sample_robot();
  PhysicsDef p = preset_gecco2018_code();
  p.duration = 3.2;
  p.gravity = -7.5;
  p.bond_damping = 0.9;
  Exported e;
  export_and_merge(robot, p, e);
  const XMLElement* vxa = e.vxa();
  ASSERT_STREQ(vxa->Name(), "VXA");

  // Simulator: everything voxcraft-sim reads there has a value (no uninitialised damping).
  EXPECT_EQ(num(vxa, "Simulator/Damping/BondDampingZ"), 0.9);
  EXPECT_EQ(num(vxa, "Simulator/Damping/ColDampingZ"), p.collision_damping);
  EXPECT_EQ(num(vxa, "Simulator/Damping/SlowDampingZ"), p.global_damping);
  EXPECT_EQ(num(vxa, "Simulator/EnableExpansion"), 1);  // else the wave only contracts
  EXPECT_EQ(num(vxa, "Simulator/AttachDetach/EnableCollision"), 1);
  EXPECT_EQ(num(vxa, "Simulator/AttachDetach/EnableAttach"), 0);
  const XMLElement* stop = at(vxa, "Simulator/StopCondition/StopConditionFormula");
  ASSERT_NE(stop, nullptr);
  EXPECT_LE(mathtree_at_time(stop, 3.2), 0);  // still running at the duration ...
  EXPECT_GT(mathtree_at_time(stop, std::nextafter(3.2, 4.0)), 0);  // ... stopped just past it

  // Environment: gravity is GravAcc alone in voxcraft-sim; floor; the temperature wave.
  EXPECT_EQ(num(vxa, "Environment/Gravity/GravAcc"), -7.5);
  EXPECT_EQ(num(vxa, "Environment/Gravity/FloorEnabled"), 1);
  EXPECT_EQ(num(vxa, "Environment/Thermal/VaryTempEnabled"), 1);
  const double temp_amp = num(vxa, "Environment/Thermal/TempAmplitude");
  const double period = num(vxa, "Environment/Thermal/TempPeriod");
  EXPECT_EQ(period, 1 / p.act_frequency);

  // VXC: a version whose layers voxcraft-sim reads; the lattice; the palette by position.
  EXPECT_STREQ(at(vxa, "VXC")->Attribute("Version"), "0.94");
  EXPECT_EQ(num(vxa, "VXC/Lattice/Lattice_Dim"), robot.voxel_size);
  std::vector<const XMLElement*> mats;
  for (const XMLElement* m = at(vxa, "VXC/Palette")->FirstChildElement("Material"); m;
       m = m->NextSiblingElement("Material"))
    mats.push_back(m);
  ASSERT_EQ(static_cast<int>(mats.size()), e.files.materials);
  EXPECT_EQ(e.files.materials, 5);  // the five levels, exactly
  EXPECT_EQ(e.files.max_stiffness_error, 0.0);
  for (const XMLElement* m : mats) {
    EXPECT_EQ(num(m, "Mechanical/MatModel"), 0);
    EXPECT_EQ(num(m, "Mechanical/Density"), p.density);
    EXPECT_EQ(num(m, "Mechanical/uStatic"), p.mu_static);
    EXPECT_EQ(num(m, "Mechanical/uDynamic"), p.mu_kinetic);
    // The settling phase: voxcraft-sim holds the temperature (size L) until then.
    EXPECT_EQ(num(m, "Mechanical/TurnOnThermalExpansionAfterThisManySeconds"), p.settle_time);
  }

  // Structure: ASCII_READABLE, id = char - 48, z layers bottom first, x fastest.
  const XMLElement* st = at(vxa, "VXC/Structure");
  EXPECT_STREQ(st->Attribute("Compression"), "ASCII_READABLE");
  const int nx = static_cast<int>(num(st, "X_Voxels")), ny = static_cast<int>(num(st, "Y_Voxels")),
            nz = static_cast<int>(num(st, "Z_Voxels"));
  ASSERT_EQ(nx, robot.nx);
  ASSERT_EQ(ny, robot.ny);
  ASSERT_EQ(nz, robot.nz);
  const XMLElement* layer = at(st, "Data/Layer");
  const XMLElement* phase_layer = at(st, "PhaseOffset/Layer");
  const double inv_range = 1 / (p.e_max - p.e_min);
  int voxels = 0;
  for (int z = 0; z < nz; ++z, layer = layer->NextSiblingElement("Layer"),
           phase_layer = phase_layer->NextSiblingElement("Layer")) {
    ASSERT_NE(layer, nullptr);
    ASSERT_NE(phase_layer, nullptr);
    const std::string data = layer->GetText();
    ASSERT_EQ(data.size(), static_cast<size_t>(nx * ny));
    std::vector<std::string> phases;
    std::stringstream ss(phase_layer->GetText());
    for (std::string v; std::getline(ss, v, ',');) phases.push_back(v);
    ASSERT_GE(phases.size(), static_cast<size_t>(nx * ny));  // voxcraft: "too short" else
    for (int k = 0; k < nx * ny; ++k) {
      const int s = z * nx * ny + k, id = data[k] - 48;
      ASSERT_GE(id, 0);
      ASSERT_LE(id, static_cast<int>(mats.size()));
      EXPECT_EQ(id > 0, robot.present[s] != 0) << "site " << s;
      if (id == 0) continue;
      ++voxels;
      const XMLElement* m = mats[id - 1];
      const double E = num(m, "Mechanical/Elastic_Mod");
      EXPECT_EQ(E, robot.stiffness[s]);
      EXPECT_EQ(std::atof(phases[k].c_str()), robot.phase[s]);
      // Size by voxcraft-sim's kernel, L (1 + TempAmplitude sin(2 pi (t/T + phase)) CTE), is
      // plastivox's L (1 + A xi(E) sin(2 pi (f t + phase))) at any time after settling.
      const double cte = num(m, "Mechanical/CTE");
      for (double t : {0.31, 1.07, 2.5}) {
        const double vc =
            1 + temp_amp * std::sin(2 * std::numbers::pi * (t / period + robot.phase[s])) * cte;
        const double pv =
            1 + p.act_amplitude * ((p.e_max - E) * inv_range) *
                    std::sin(2 * std::numbers::pi * (p.act_frequency * t + robot.phase[s]));
        EXPECT_NEAR(vc, pv, 1e-12) << "site " << s << " at t = " << t;
      }
    }
  }
  EXPECT_EQ(voxels, robot.voxel_count());

  // Time step: voxcraft-sim's DtFrac / (2 pi sqrt(max over bonds of E_bond L / m)) equals
  // plastivox's dt for this robot.
  double k_bond = 0;
  for (int s = 0; s < robot.sites(); ++s)
    for (int d : {1, robot.nx, robot.nx * robot.ny}) {
      const int x = s % robot.nx, y = (s / robot.nx) % robot.ny, z = s / (robot.nx * robot.ny);
      const bool inside = d == 1          ? x + 1 < robot.nx
                          : d == robot.nx ? y + 1 < robot.ny
                                          : z + 1 < robot.nz;
      if (!inside || !robot.present[s] || !robot.present[s + d]) continue;
      const double a = robot.stiffness[s], b = robot.stiffness[s + d];
      k_bond = std::max(k_bond, 2 * a * b / (a + b) * robot.voxel_size);
    }
  const double mass = p.density * std::pow(robot.voxel_size, 3);
  const double dt_vc =
      num(vxa, "Simulator/Integration/DtFrac") / (2 * std::numbers::pi * std::sqrt(k_bond / mass));
  EXPECT_TRUE(testing::RelNear(dt_vc, Simulator(compile(robot, p)).state().dt, 1e-12));
}

TEST(VoxcraftExport, LayersEscapeTheMarkupCharactersOfLargePalettes) {
  // 78 levels: ids 12 and 14 are '<' and '>' in an ASCII_READABLE layer.
  RobotDef r = testing::block(13, 6, 1, 1e6);
  for (int s = 0; s < r.sites(); ++s) r.stiffness[s] = 1e6 * std::pow(1.1, s);
  Exported e;
  export_and_merge(r, preset_gecco2018_code(), e);
  EXPECT_EQ(e.files.materials, 78);
  EXPECT_NE(e.files.robot_vxd.find("&lt;"), std::string::npos);
  const std::string data = at(e.vxa(), "VXC/Structure/Data/Layer")->GetText();
  for (int s = 0; s < r.sites(); ++s) EXPECT_EQ(data[s] - 48, s + 1);
  EXPECT_EQ(e.files.max_stiffness_error, 0.0);
}

TEST(VoxcraftExport, WhatVoxcraftCannotExpressIsRefusedInOneLineOrDroppedWithALine) {
  RobotDef r = sample_robot();
  PhysicsDef p = preset_gecco2018_code();
  p.treatment = Treatment::kStress;
  r.dev_rate[0] = 2.0;
  try {
    write_voxcraft(r, p, false);
    ADD_FAILURE() << "development was not refused";
  } catch (const VxaError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("development (treatment stress, 1 voxels"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  r.fixed_sites = {0};
  const VoxcraftFiles lossy = write_voxcraft(r, p, true);
  ASSERT_EQ(lossy.dropped.size(), 2u);
  EXPECT_NE(lossy.dropped[0].find("development"), std::string::npos);
  EXPECT_NE(lossy.dropped[1].find("fixed voxels"), std::string::npos);
  // The world and the task: refused, or dropped with a line.
  PhysicsDef world = preset_gecco2018_code();
  world.environment.obstacles.push_back({{0.1, 0.1, 0}, {0.2, 0.2, 0.01}});
  world.task = Task::kTurn;
  EXPECT_THROW(write_voxcraft(sample_robot(), world, false), VxaError);
  const VoxcraftFiles dropped = write_voxcraft(sample_robot(), world, true);
  ASSERT_EQ(dropped.dropped.size(), 2u);
  EXPECT_NE(dropped.dropped[0].find("physics.environment"), std::string::npos);
  EXPECT_NE(dropped.dropped[1].find("physics.task 'turn'"), std::string::npos);
  PhysicsDef floor = preset_gecco2018_code();
  floor.act_min_factor = 0.9;  // the 14 % wave reaches it
  EXPECT_THROW(write_voxcraft(sample_robot(), floor, false), VxaError);
}

// ---- import ----------------------------------------------------------------------------

// The final lowest voxel centre and the status of a life of `v` lasting `duration` s.
struct Life {
  SimResult result;
  double lowest = 0;  // m
};
Life live(const VxaRobot& v, double duration) {
  PhysicsDef p = v.physics;
  p.duration = duration;
  const Model m = compile(v.robot, p);
  Simulator sim(m);
  while (sim.state().status == SimStatus::kRunning) sim.step();  // to the end of the life
  Life l;
  l.result.status = sim.state().status;
  l.lowest = 1e9;
  for (const Vec3& x : sim.state().pos) l.lowest = std::min(l.lowest, x.z());
  return l;
}

TEST(VoxcraftImport, TheBasicDemoFallsOntoTheFloorAndStands) {
  const VxaRobot v = read_voxcraft(kDemos + "basic/base.vxa", kDemos + "basic/robot.vxd");
  EXPECT_EQ(v.robot.voxel_count(), 1);
  EXPECT_TRUE(v.robot.present[1]);  // the top one of a 1x1x2 lattice
  EXPECT_EQ(v.robot.stiffness[1], 1e5);
  EXPECT_EQ(v.robot.act_amplitude[1], 0.0);
  EXPECT_EQ(v.physics.density, 1e3);
  EXPECT_EQ(v.physics.duration, 1.0);   // t - 1
  EXPECT_EQ(v.physics.gravity, -9.81);  // no <Environment>: voxcraft-sim's defaults
  EXPECT_TRUE(v.physics.floor);
  EXPECT_EQ(v.physics.mu_kinetic, 0.8);
  EXPECT_EQ(v.physics.global_damping, 1.0);  // <Damping> defaults, with a warning
  ASSERT_EQ(v.warnings.size(), 1u);
  EXPECT_NE(v.warnings[0].find("no <Damping>"), std::string::npos) << v.warnings[0];
  // Critically slow-damped, it sinks 1 cm in about 2 s; by 4 s it rests on the floor.
  const Life l = live(v, 4.0);
  EXPECT_EQ(l.result.status, SimStatus::kFinished);
  EXPECT_NEAR(l.lowest, 0.5 * v.robot.voxel_size, 0.01 * v.robot.voxel_size);
}

TEST(VoxcraftImport, TheBigbuyDemoActuatesItsMuscleAndWalksStably) {
  const VxaRobot v = read_voxcraft(kDemos + "bigbuy/base.vxa", kDemos + "bigbuy/robot_0000.vxd");
  const RobotDef& r = v.robot;
  ASSERT_EQ(r.nx * r.ny * r.nz, 27);  // the .vxd's structure replaced the base's 6x6x5
  EXPECT_EQ(r.voxel_count(), 21);
  EXPECT_EQ(r.stiffness[0], 3e7);  // '1': muscle
  EXPECT_EQ(r.act_amplitude[0], 7.72173 * 0.01);
  EXPECT_EQ(r.stiffness[1], 3e9);  // '2': bone, no CTE
  EXPECT_EQ(r.act_amplitude[1], 0.0);
  EXPECT_EQ(r.phase[0], 0.437);
  EXPECT_EQ(v.physics.act_frequency, 5.0);  // TempPeriod 0.2
  EXPECT_FALSE(v.physics.act_expansion);    // no EnableExpansion: contraction only
  EXPECT_EQ(v.physics.duration, 2.0);
  EXPECT_EQ(v.physics.settle_time, 0.0);
  EXPECT_EQ(v.physics.bond_damping, 1.0);
  EXPECT_EQ(v.physics.collision_damping, 0.8);
  EXPECT_EQ(v.physics.global_damping, 0.01);
  EXPECT_EQ(v.physics.global_damping_rot_factor, 1.0);
  EXPECT_EQ(v.physics.poisson, 0.0);  // zeroed without VolumeEffectsEnabled
  EXPECT_EQ(v.physics.density, 1e6);
  EXPECT_TRUE(v.physics.self_collision);
  // The muscle voxel contracts and never swells.
  PhysicsDef p = v.physics;
  const Model m = compile(r, p);
  Simulator sim(m);
  double smallest = 1, largest = 0;
  while (sim.state().time < 0.4) {
    sim.step();
    smallest = std::min(smallest, sim.state().size[0] / m.size);
    largest = std::max(largest, sim.state().size[0] / m.size);
  }
  EXPECT_NEAR(smallest, 1 - 0.0772173, 1e-4);
  EXPECT_EQ(largest, 1.0);
  EXPECT_EQ(sim.state().size[1], m.size);  // bone does not move
  // The whole life: stable, standing on the floor.
  const Life l = live(v, v.physics.duration);
  EXPECT_EQ(l.result.status, SimStatus::kFinished);
  EXPECT_NEAR(l.lowest, 0.5 * r.voxel_size, 0.1 * r.voxel_size);
}

TEST(VoxcraftImport, FeaturesPlastivoxDoesNotModelAreNamedInOneLine) {
  std::string base = testing::file_text(kDemos + "bigbuy/base.vxa");
  const std::string vxd = testing::file_text(kDemos + "bigbuy/robot_0000.vxd");
  base.replace(base.find("<EnableAttach>0"), 15, "<EnableAttach>1");
  base.replace(base.find("<Simulator>"), 11, "<Simulator><EnableCilia>1</EnableCilia>");
  try {
    parse_voxcraft(base, "base.vxa", vxd, "robot.vxd");
    ADD_FAILURE() << "cilia and attachment were accepted";
  } catch (const VxaError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos);
    EXPECT_NE(what.find("base.vxa + robot.vxd: voxcraft-sim features plastivox does not model: "
                        "cilia (<Simulator>/<EnableCilia>), attachment"),
              std::string::npos)
        << what;
  }
  // A stop condition on anything but time.
  std::string on_x = testing::file_text(kDemos + "bigbuy/base.vxa");
  on_x.replace(on_x.find("<mtVAR>t</mtVAR>\n          <mtCONST>2"), 16, "<mtVAR>x</mtVAR>");
  try {
    parse_voxcraft(on_x, "base.vxa", vxd, "robot.vxd");
    ADD_FAILURE() << "a stop condition on x was accepted";
  } catch (const VxaError& e) {
    EXPECT_NE(std::string(e.what()).find("reads the variable 'x'"), std::string::npos) << e.what();
  }
  // A material id beyond the palette.
  std::string bad = vxd;
  bad.replace(bad.find("120220222"), 9, "129220222");
  EXPECT_THROW(
      parse_voxcraft(testing::file_text(kDemos + "bigbuy/base.vxa"), "base.vxa", bad, "robot.vxd"),
      VxaError);
}

TEST(VoxcraftImport, DamagedFilesGiveOneLineErrorsNeverACrash) {
  const std::string base = testing::file_text(kDemos + "bigbuy/base.vxa");
  const std::string vxd = testing::file_text(kDemos + "bigbuy/robot_0000.vxd");
  int refused = 0;
  auto check = [&](const std::string& b, const std::string& v) {
    try {
      parse_voxcraft(b, "base.vxa", v, "robot.vxd");
    } catch (const VxaError& e) {
      ++refused;
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_TRUE(what.starts_with("base.vxa") || what.starts_with("robot.vxd")) << what;
    }
  };
  int cuts = 0;
  for (size_t cut = 0; cut < base.size(); cut += 61, ++cuts) check(base.substr(0, cut), vxd);
  for (size_t cut = 0; cut < vxd.size(); cut += 61, ++cuts) check(base, vxd.substr(0, cut));
  EXPECT_EQ(refused, cuts);  // a truncated file is never read as a robot
  // Values that are not numbers, in either file.
  std::string bad_base = base, bad_vxd = vxd;
  bad_base.replace(bad_base.find("0.01</CTE>"), 4, "abcd");
  bad_vxd.replace(bad_vxd.find("0.437"), 5, "0.4.7");
  check(bad_base, vxd);
  check(base, bad_vxd);
  EXPECT_EQ(refused, cuts + 2);
}

// ---- round trip ------------------------------------------------------------------------

// plastivox's own rules that voxcraft-sim fixes otherwise (Poisson's ratio in torsion, the
// rotational slow damping factor, the size floor): what import gives and export cannot carry.
PhysicsDef with_plastivox_rules(PhysicsDef p, const PhysicsDef& original) {
  p.poisson = original.poisson;
  p.global_damping_rot_factor = original.global_damping_rot_factor;
  p.act_min_factor = original.act_min_factor;
  return p;
}

TEST(VoxcraftRoundTrip, APaletteThatHoldsEveryModulusGivesTheSameLifeBitForBit) {
  const RobotDef robot = sample_robot();
  PhysicsDef p = preset_gecco2018_code();
  p.duration = 1.2;
  const VoxcraftFiles f = write_voxcraft(robot, p, false);
  const VxaRobot back = parse_voxcraft(f.base_vxa, "base.vxa", f.robot_vxd, "robot.vxd");
  EXPECT_TRUE(back.warnings.empty());
  EXPECT_EQ(back.robot.present, robot.present);
  for (int s = 0; s < robot.sites(); ++s) {
    if (!robot.present[s]) continue;
    EXPECT_EQ(back.robot.stiffness[s], robot.stiffness[s]);
    EXPECT_EQ(back.robot.phase[s], robot.phase[s]);
  }
  const PhysicsDef& q = back.physics;
  EXPECT_EQ(q.gravity, p.gravity);
  EXPECT_EQ(q.floor, p.floor);
  EXPECT_EQ(q.self_collision, p.self_collision);
  EXPECT_EQ(q.bond_damping, p.bond_damping);
  EXPECT_EQ(q.collision_damping, p.collision_damping);
  EXPECT_EQ(q.global_damping, p.global_damping);
  EXPECT_EQ(q.density, p.density);
  EXPECT_EQ(q.mu_static, p.mu_static);
  EXPECT_EQ(q.mu_kinetic, p.mu_kinetic);
  EXPECT_EQ(q.settle_time, p.settle_time);
  EXPECT_EQ(q.duration, p.duration);
  EXPECT_EQ(q.act_frequency, p.act_frequency);
  EXPECT_EQ(q.act_expansion, p.act_expansion);
  EXPECT_EQ(q.dt_frac, p.dt_frac);
  // voxcraft-sim's fixed rules come back as such.
  EXPECT_EQ(q.poisson, 0.0);
  EXPECT_EQ(q.global_damping_rot_factor, 1.0);
  // The same life: per-voxel amplitudes equal A xi(E) bit for bit.
  const SimResult a = simulate(compile(robot, p));
  const SimResult b = simulate(compile(back.robot, with_plastivox_rules(q, p)));
  EXPECT_EQ(a.status, SimStatus::kFinished) << a.failure;
  EXPECT_EQ(b.final_state_hash, a.final_state_hash);
  EXPECT_EQ(b.fitness, a.fitness);
}

TEST(VoxcraftRoundTrip, AContinuousStiffnessFieldComesBackToThePalettesQuantisation) {
  // 512 voxels with as many distinct moduli over two decades: at most 78 levels.
  RobotDef robot = testing::block(8, 8, 8, 1e8);
  for (int s = 0; s < robot.sites(); ++s) {
    const int x = s % 8, y = (s / 8) % 8, z = s / 64;
    robot.stiffness[s] = 1e8 * std::pow(1e2, (x + 8 * y + 64 * z) / 511.0);
    robot.phase[s] = 0.1 * x - 0.05 * z;
  }
  PhysicsDef p = preset_gecco2018_code();
  p.duration = 1.2;
  const VoxcraftFiles f = write_voxcraft(robot, p, false);
  EXPECT_LE(f.materials, 78);                                 // the narrowest cover may need fewer
  const double bound = std::exp(std::log(1e2) / 78 / 2) - 1;  // 3.0 %
  EXPECT_LE(f.max_stiffness_error, bound + 1e-12);
  const VxaRobot back = parse_voxcraft(f.base_vxa, "base.vxa", f.robot_vxd, "robot.vxd");
  double worst = 0;
  for (int s = 0; s < robot.sites(); ++s) {
    const double rel = std::abs(back.robot.stiffness[s] - robot.stiffness[s]) / robot.stiffness[s];
    worst = std::max(worst, rel);
    EXPECT_EQ(back.robot.phase[s], robot.phase[s]);
    // The amplitude is the paper's A xi at the voxel's palette modulus.
    const double xi_q = (p.e_max - back.robot.stiffness[s]) / (p.e_max - p.e_min);
    EXPECT_NEAR(back.robot.act_amplitude[s], p.act_amplitude * xi_q, 1e-15);
  }
  EXPECT_EQ(worst, f.max_stiffness_error);
  // The life, under plastivox's own rules, stays close to the original.
  const SimResult a = simulate(compile(robot, p));
  const SimResult b = simulate(compile(back.robot, with_plastivox_rules(back.physics, p)));
  ASSERT_EQ(a.status, SimStatus::kFinished) << a.failure;
  ASSERT_EQ(b.status, SimStatus::kFinished) << b.failure;
  EXPECT_TRUE(testing::RelNear(b.com_final.z(), a.com_final.z(), 0.01));
  EXPECT_NEAR(b.displacement.x(), a.displacement.x(), 0.05);
}

}  // namespace
}  // namespace plastivox
