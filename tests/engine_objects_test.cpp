// Free objects (docs/environments.md, "Free objects"): passive voxel boxes of the world,
// compiled after the robot's voxels (Model::robot_n). Physics against analytic answers
// (momentum through a push without friction, a box at rest on the floor, a payload at rest on
// a still body), the robot's accounting without them, the tasks carry and push on hand-made
// cases, and bad definitions named by file and field.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::block;
using testing::error_of;
using testing::passive_physics;
using testing::run_until;
using testing::with_environment;

Vec3 total_momentum(const State& s) {
  Vec3 p = Vec3::Zero();
  for (const Vec3& v : s.lin_mom) p += v;
  return p;
}

// Centre of object k, m.
Vec3 object_centre(const Model& m, const State& s, int k) {
  Vec3 c = Vec3::Zero();
  for (int i = m.object_begin[k]; i < m.object_begin[k + 1]; ++i) c += s.pos[i];
  return c / (m.object_begin[k + 1] - m.object_begin[k]);
}

// ---- Compiling ----

TEST(Objects, CompileAppendsPassiveObjectVoxelsAfterTheRobot) {
  const Model m = compile(block(2, 1, 1, 1e6), with_environment(passive_physics(), R"({"objects": [
                            {"voxels": [2, 2, 1], "at": [0.1, 0, 0]},
                            {"voxels": [1, 1, 3], "at": [0.2, 0, 0], "stiffness": 5e6}]})"));
  ASSERT_EQ(m.robot_n, 2);
  ASSERT_EQ(m.n, 2 + 4 + 3);
  EXPECT_EQ(m.object_begin, (std::vector<int>{2, 6, 9}));
  // The first object's voxels, x fastest; its four bonds, the other's two, the robot's one.
  EXPECT_LT((m.rest_pos[2] - Vec3(0.105, 0.005, 0.005)).norm(), 1e-15);
  EXPECT_LT((m.rest_pos[5] - Vec3(0.115, 0.015, 0.005)).norm(), 1e-15);
  EXPECT_LT((m.rest_pos[8] - Vec3(0.205, 0.005, 0.025)).norm(), 1e-15);
  EXPECT_EQ(m.bond_count(), 1 + 4 + 2);
  for (int i = m.robot_n; i < m.n; ++i) {
    EXPECT_EQ(m.site[i], -1);
    EXPECT_EQ(m.act_gain[i], 0.0);          // passive
    EXPECT_EQ(m.alpha[i], 0.0);             // no development
    EXPECT_EQ(m.e0[i], i < 6 ? 1e6 : 5e6);  // default: the robot's stiffest voxel's
  }
  for (int b = 1; b < m.bond_count(); ++b) EXPECT_GE(m.bond_a[b], m.robot_n);
}

// An object far from the robot changes nothing of the robot's life, bit for bit: it is out
// of the centre of mass, the fitness, the voxel count and the stiffness statistics, takes no
// part in the time step (its stiffness is the robot's stiffest) and never touches the robot.
TEST(Objects, AFarObjectLeavesTheRobotsLifeBitForBit) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.duration = 0.8;
  const SimResult plain = simulate(compile(demo_walker(), d));
  const Model m = compile(demo_walker(), with_environment(d, R"({"objects": [{"voxels": [2, 2, 2],
                                                    "at": [-1, -1, 0]}]})"));
  ASSERT_GT(m.n, m.robot_n);
  const SimResult r = simulate(m);
  ASSERT_EQ(r.status, SimStatus::kFinished);
  EXPECT_EQ(r.voxels, plain.voxels);
  EXPECT_EQ(r.fitness, plain.fitness);
  EXPECT_EQ(r.com_final, plain.com_final);
  EXPECT_EQ(r.com_settled, plain.com_settled);
  EXPECT_EQ(r.final_stiffness, plain.final_stiffness);
  EXPECT_EQ(r.stiffness_change_mean, plain.stiffness_change_mean);
  EXPECT_EQ(r.steps, plain.steps);
  EXPECT_NE(r.final_state_hash, plain.final_state_hash);  // the state holds the box too
}

// With self_collision off, the contact search that runs for an object leaves the robot's own
// pairs out: two unbonded voxels of one robot thrown at each other in space pass through each
// other as they do without the object (and bounce apart with self_collision on).
TEST(Objects, WithSelfCollisionOffTheRobotStillPassesThroughItself) {
  RobotDef r = make_empty_robot(4, 1, 1);
  for (int x : {0, 3}) r.present[r.site(x, 0, 0)] = 1, r.stiffness[r.site(x, 0, 0)] = 1e9;
  const auto final_x = [&](bool self_collision, const char* environment) {
    PhysicsDef d = with_environment(passive_physics(), environment);
    d.gravity = 0, d.floor = false, d.duration = 0.3;
    d.self_collision = self_collision;
    const Model m = compile(r, d);
    Simulator sim(m);
    sim.mutable_state().lin_mom[0] = Vec3(m.mass * 0.5, 0, 0);  // at 0.5 m/s along +x
    run_until(sim, d.duration);
    return std::vector<double>{sim.state().pos[0].x(), sim.state().pos[1].x()};
  };
  const char* far_box = R"({"objects": [{"voxels": [1, 1, 1], "at": [5, 5, 5]}]})";
  const std::vector<double> alone = final_x(false, "{}");
  EXPECT_GT(alone[0], alone[1]);  // passed through
  EXPECT_EQ(final_x(false, far_box), alone);
  const std::vector<double> colliding = final_x(true, far_box);
  EXPECT_LT(colliding[0], colliding[1]);  // bounced
}

// ---- Physics against analytic answers ----

// A 2 x 2 x 2 body thrown at 0.5 m/s along +x at a free box of the same size one voxel away,
// in space (no gravity, no floor, no slow damping): the contact's forces are equal and
// opposite, so the total momentum stays 8 m v through the push, with friction off and on
// (the contact's friction is internal too), and the box leaves with much of it (half in a
// perfectly inelastic push).
TEST(Objects, APushConservesMomentumWithoutFriction) {
  for (const double mu : {0.0, 0.5}) {
    PhysicsDef d = passive_physics();
    d.gravity = 0, d.floor = false, d.global_damping = 0;
    d.mu_static = mu, d.mu_kinetic = mu;
    d.duration = 0.3;
    const Model m =
        compile(block(2, 2, 2, 1e9), with_environment(d, R"({"objects": [{"voxels": [2, 2, 2],
                                                      "at": [0.03, 0.005, 0]}]})"));
    Simulator sim(m);
    const double v = 0.5;
    for (int i = 0; i < m.robot_n; ++i) sim.mutable_state().lin_mom[i] = Vec3(m.mass * v, 0, 0);
    const Vec3 before = total_momentum(sim.state());
    run_until(sim, d.duration);
    const State& s = sim.state();
    ASSERT_EQ(s.status, SimStatus::kFinished) << s.failure;
    const Vec3 after = total_momentum(s);
    EXPECT_NEAR((after - before).norm() / before.norm(), 0, 1e-12) << "mu " << mu;
    Vec3 box = Vec3::Zero();
    for (int i = m.robot_n; i < m.n; ++i) box += s.lin_mom[i];
    EXPECT_GT(box.x(), 0.4 * before.x()) << "mu " << mu << ": the box was not pushed";
    EXPECT_GT(object_centre(m, s, 0).x(), 0.04);  // it moved off along +x
  }
}

// A free 2 x 2 x 2 box dropped 2 mm onto the floor comes to rest with its centre at its half
// height L, less the sag under its weight: the bottom voxels press m g / (2 E L) deeper per
// voxel above them (2 m g over the floor's 2 E L), and the bond between the layers shortens by
// m g / (E L), so the centre sits 1.5 m g / (E L) low.
TEST(Objects, ABoxDroppedOnTheFloorRestsAtItsHalfHeight) {
  PhysicsDef d = passive_physics();
  d.duration = 1.5;
  const double E = 1e10, L = 0.01;
  const Model m =
      compile(block(1, 1, 1, E), with_environment(d, R"({"objects": [{"voxels": [2, 2, 2],
                                                    "at": [0.1, 0.2, 0.002]}]})"));
  Simulator sim(m);
  run_until(sim, d.duration);
  const State& s = sim.state();
  ASSERT_EQ(s.status, SimStatus::kFinished) << s.failure;
  const double sag = m.mass * -d.gravity / (E * L);
  const Vec3 c = object_centre(m, s, 0);
  EXPECT_NEAR(c.z(), L - 1.5 * sag, 1e-7);
  EXPECT_NEAR(c.x(), 0.1 + L, 1e-12);
  EXPECT_NEAR(c.y(), 0.2 + L, 1e-12);
  for (int i = m.robot_n; i < m.n; ++i) EXPECT_LT(s.lin_mom[i].norm() / m.mass, 1e-4);
}

// The carry task's payload (a 2 x 2 x 1 slab, the default) on a still 4 x 4 x 2 body on the
// floor stays where it was put: it never moves sideways, rests on the voxels under it with
// their contact pressed in by its weight, m g / (E L) (each payload voxel on one body voxel,
// both of modulus E), never comes near the ground, and carry scores 0.
TEST(Objects, APayloadRestingOnAStillBodyStays) {
  PhysicsDef d = passive_physics();
  d.duration = 1.5;
  d.task = Task::kCarry;
  const double E = 1e9, L = 0.01;
  const RobotDef body = block(4, 4, 2, E);
  const Model m = compile(body, d);
  ASSERT_EQ(m.object_count(), 1);
  const int under = m.robot_n - 16 + 1 + 4 * 1;  // the top-layer voxel under payload voxel 0
  Simulator sim(m);
  double drift = 0, lowest_gap = 1;
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    const State& s = sim.state();
    const Vec3 c = object_centre(m, s, 0);
    drift = std::max(drift, std::hypot(c.x() - 2 * L, c.y() - 2 * L));
    lowest_gap = std::min(lowest_gap, s.pos[m.robot_n].z() - s.pos[under].z());
  }
  const State& s = sim.state();
  ASSERT_EQ(s.status, SimStatus::kFinished) << s.failure;
  EXPECT_LT(drift, 1e-6);  // m: centred on the body, where it was put, all life
  const double overlap = m.mass * -d.gravity / (E * L);
  // At rest on the voxel under it (within 2 % of the overlap: the body's top sags a little).
  EXPECT_NEAR(s.pos[m.robot_n].z() - s.pos[under].z(), L - overlap, 2e-6);
  EXPECT_GT(lowest_gap, 0.5 * L);  // on top all along, never pushed into the body
  for (int i = m.robot_n; i < m.n; ++i) EXPECT_LT(s.lin_mom[i].norm() / m.mass, 1e-4);
  const SimResult r = simulate(m);
  EXPECT_EQ(r.status, SimStatus::kFinished);
  EXPECT_LT(r.fitness, 1e-4);
}

// ---- The tasks on hand-made cases ----

// A model under `task` and its state at the end of settling, for feeding a watch by hand.
struct Settled {
  Model model;
  State state;
};
Settled settled_body(Task task) {
  PhysicsDef d = passive_physics();
  d.gravity = 0;
  d.task = task;
  Settled b{compile(block(3, 2, 2, 1e6), d), {}};
  b.state = Simulator(b.model).state();
  b.state.settled = true;
  b.state.com_settled = body_center_of_mass(b.model, b.state);
  return b;
}

// The state with the robot moved by `body` and the object by `object` (m).
State moved(const Settled& b, const Vec3& body, const Vec3& object) {
  State s = b.state;
  for (int i = 0; i < b.model.n; ++i) s.pos[i] += i < b.model.robot_n ? body : object;
  return s;
}

double score_after(const Settled& b, const std::vector<State>& states) {
  return testing::task_score_after(b.model, b.state, states);
}

TEST(Objects, TasksPlaceTheirObjectsFromTheBodysBounds) {
  const double L = 0.01;
  // push: a 2 x 2 x 2 box on the floor, one voxel length beyond the +x face, centred in y.
  const Settled push = settled_body(Task::kPush);
  ASSERT_EQ(push.model.object_count(), 1);
  EXPECT_EQ(push.model.n - push.model.robot_n, 8);
  EXPECT_LT((push.model.rest_pos[push.model.robot_n] - Vec3(4.5 * L, 0.5 * L, 0.5 * L)).norm(),
            1e-15);
  // carry: a 2 x 2 x 1 slab on the body's top, centred in x and y.
  const Settled carry = settled_body(Task::kCarry);
  EXPECT_EQ(carry.model.n - carry.model.robot_n, 4);
  EXPECT_LT((carry.model.rest_pos[carry.model.robot_n] - Vec3(1.0 * L, 0.5 * L, 2.5 * L)).norm(),
            1e-15);
  // Objects the environment gives replace the default; other tasks place none.
  PhysicsDef d = with_environment(passive_physics(), R"({"objects": [{"voxels": [1, 1, 1],
                                                       "at": [1, 1, 0]}]})");
  d.task = Task::kPush;
  EXPECT_EQ(compile(block(3, 2, 2, 1e6), d).n, 12 + 1);
  EXPECT_EQ(settled_body(Task::kWalk).model.n, 12);
}

TEST(Objects, PushScoresTheBoxsHorizontalDisplacement) {
  const Settled b = settled_body(Task::kPush);
  const double L = b.model.size;
  // A body that does not move, or walks while the box stays, scores 0.
  EXPECT_EQ(score_after(b, {b.state}), 0.0);
  EXPECT_EQ(score_after(b, {moved(b, Vec3(5 * L, 0, 0), Vec3::Zero())}), 0.0);
  // The box moved 3 voxel lengths along x and 4 along y: 5; its rise does not count.
  EXPECT_NEAR(score_after(b, {moved(b, Vec3(L, 0, 0), Vec3(3 * L, 4 * L, 2 * L))}), 5.0, 1e-12);
  // Only the end counts.
  EXPECT_NEAR(score_after(b, {moved(b, Vec3::Zero(), Vec3(9 * L, 0, 0)),
                              moved(b, Vec3::Zero(), Vec3(2 * L, 0, 0))}),
              2.0, 1e-12);
}

TEST(Objects, CarryScoresThePayloadsTravelUntilItFalls) {
  const Settled b = settled_body(Task::kCarry);
  const double L = b.model.size;
  EXPECT_EQ(score_after(b, {b.state}), 0.0);
  // Carried 3 voxel lengths along x, body and payload together.
  const State three = moved(b, Vec3(3 * L, 0, 0), Vec3(3 * L, 0, 0));
  EXPECT_NEAR(score_after(b, {three}), 3.0, 1e-12);
  // Then dropped: a payload voxel within a voxel length of the ground ends the carry; what
  // follows (carried on, even picked up again) does not count.
  const State dropped = moved(b, Vec3(3 * L, 0, 0), Vec3(4 * L, 0, -1.6 * L));
  const State later = moved(b, Vec3(8 * L, 0, 0), Vec3(8 * L, 0, 0));
  EXPECT_NEAR(score_after(b, {three, dropped, later}), 3.0, 1e-12);
  // Both must travel: a payload sliding 4 voxel lengths along a body that moved 1 scores 1;
  // a body walking 5 from under a payload that moved 2 (still up) scores 2.
  EXPECT_NEAR(score_after(b, {moved(b, Vec3(L, 0, 0), Vec3(4 * L, 0, 0))}), 1.0, 1e-12);
  EXPECT_NEAR(score_after(b, {moved(b, Vec3(5 * L, 0, 0), Vec3(2 * L, 0, 0))}), 2.0, 1e-12);
  // A payload already on the ground when settling ends scores 0.
  Settled off = b;
  off.state = moved(b, Vec3::Zero(), Vec3(0, 0, -2 * L));
  EXPECT_EQ(score_after(off, {moved(b, Vec3(3 * L, 0, 0), Vec3(3 * L, 0, -2 * L))}), 0.0);
}

// A life, not a watch fed by hand: a passive body on the floor never reaches the box, which
// rests where it was put: push scores 0.
TEST(Objects, ABodyThatDoesNotMoveScoresZeroOnPush) {
  PhysicsDef d = passive_physics();
  d.duration = 1.0;
  d.task = Task::kPush;
  const SimResult r = simulate(compile(block(3, 2, 2, 1e8), d));
  ASSERT_EQ(r.status, SimStatus::kFinished) << r.failure;
  EXPECT_EQ(r.voxels, 12);
  EXPECT_LT(r.fitness, 1e-9);
}

// ---- JSON ----

std::string robot_with_environment(const std::string& env) {
  return R"({"format": "plastivox-robot", "version": 1, "lattice": {"nx": 1, "ny": 1, "nz": 1,
    "voxel_size": 0.01}, "voxels": [[0, 0, 0, 1e9, 0, 0]], "physics": {"environment": )" +
         env + "}}";
}

TEST(ObjectsJson, RobotFileRoundTripsObjects) {
  const char* env = R"({"ground": {"type": "flat"}, "objects": [{"voxels": [2, 3, 1],
                        "at": [0.1, -0.02, 0]}, {"voxels": [1, 1, 1], "at": [0, 0, 0.05],
                        "stiffness": 2e7}]})";
  const RobotFile a = parse_robot_json(robot_with_environment(env), "a.json");
  ASSERT_EQ(a.physics.environment.objects.size(), 2u);
  EXPECT_EQ(a.physics.environment.objects[1].stiffness, 2e7);
  const std::string text = robot_to_json(a.robot, &a.physics);
  const RobotFile b = parse_robot_json(text, "b.json");
  EXPECT_EQ(b.physics.environment, a.physics.environment);
  EXPECT_EQ(robot_to_json(b.robot, &b.physics), text);
  // Objects alone: written back, and the floor kernel still runs (no terrain path).
  const RobotFile c = parse_robot_json(
      robot_with_environment(R"({"objects": [{"voxels": [1, 1, 1], "at": [1, 0, 0]}]})"), "c.json");
  EXPECT_NE(robot_to_json(c.robot, &c.physics).find("\"objects\""), std::string::npos);
  EXPECT_FALSE(compile(c.robot, c.physics).terrain);
}

TEST(ObjectsJson, BadDefinitionsNameTheFileAndField) {
  const std::string o = "f.json: physics.environment.objects";
  const std::pair<const char*, std::string> cases[] = {
      {R"({"objects": {"voxels": [1, 1, 1]}})",
       o + ": expected an array of {\"voxels\": [nx, ny, nz], \"at\": [x, y, z]}"},
      {R"({"objects": [{"at": [0, 0, 0]}]})", o + "[0].voxels: missing (the extent [nx, ny, nz])"},
      {R"({"objects": [{"voxels": [1, 1, 1]}]})",
       o + "[0].at: missing (the lowest corner [x, y, z], m)"},
      {R"({"objects": [{"voxels": [1, 1], "at": [0, 0, 0]}]})",
       o + "[0].voxels: expected [nx, ny, nz], whole voxels along x, y and z"},
      {R"({"objects": [{"voxels": [1, 0, 1], "at": [0, 0, 0]}]})",
       o + "[0].voxels[1]: must be in [1, 1000], got 0"},
      {R"({"objects": [{"voxels": [1, 1.5, 1], "at": [0, 0, 0]}]})",
       o + "[0].voxels[1]: expected an integer in [1, 1000]"},
      {R"({"objects": [{"voxels": [1, 1, 1], "at": [0, "x", 0]}]})",
       o + "[0].at[1]: expected a number"},
      {R"({"objects": [{"voxels": [1, 1, 1], "at": [0, 0, 2e6]}]})",
       o + "[0].at: must be finite, within 1e6 m"},
      {R"({"objects": [{"voxels": [1, 1, 1], "at": [0, 0, 0]}, {"voxels": [1, 1, 1],
           "at": [0, 0, 0], "stiffness": -1}]})",
       o + "[1].stiffness: must be in [0, 1e12] Pa (0: the robot's stiffest voxel's)"},
      {R"({"objects": [{"voxels": [1, 1, 1], "at": [0, 0, 0], "mass": 1}]})",
       o + "[0].mass: unknown field"},
      {R"({"objects": [{"voxels": [1000, 1000, 1], "at": [0, 0, 0]}]})",
       o + "[0].voxels: the objects hold more than 262144 voxels"},
  };
  for (const auto& [env, message] : cases)
    EXPECT_EQ(error_of([&] { parse_robot_json(robot_with_environment(env), "f.json"); }), message)
        << env;
}

class ObjectsCli : public testing::ScratchDirTest {};

TEST_F(ObjectsCli, ProgramRefusesABadObjectInOneLine) {
  std::ofstream(path("bad.json")) << robot_with_environment(
      R"({"objects": [{"voxels": [1, 1, 1], "at": [0, 0, 0], "stiffness": "hard"}]})");
  const testing::Output out =
      testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + path("bad.json") + " 2>&1");
  EXPECT_NE(out.status, 0);
  EXPECT_EQ(out.out, "plastivox simulate: error: " + path("bad.json") +
                         ": physics.environment.objects[0].stiffness: expected a number\n");
}

}  // namespace
}  // namespace plastivox
