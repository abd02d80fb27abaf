#include "plastivox/render/life.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/render/offscreen.hpp"  // RenderError
#include "plastivox/robot_file.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/vxa.hpp"

namespace plastivox::render {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Frame capture(const State& s) {
  Frame f;
  f.time = s.time;
  f.pos = s.pos;
  f.orient = s.orient;
  f.size = s.size;
  f.stiffness = s.stiffness;
  f.stimulus = s.stimulus;
  return f;
}

}  // namespace

LifeSource load_life_source(const std::string& path, int generation) {
  if (ends_with(path, ".h5") && evo::is_life_file(path)) return recorded_life_source(path);
  LifeSource src;
  src.path = path;
  if (ends_with(path, ".h5")) {
    const evo::ResultsFile results = evo::read_results(path);
    const evo::RunState& run = results.state;
    const evo::ChampionRecord& champion = evo::champion_at(run, generation, path);
    src.robot = evo::champion_robot(champion, generation < 0 ? run.generations_done : generation);
    src.physics = run.config.physics;
    src.label =
        std::string(to_string(run.config.treatment)) + " · seed " + std::to_string(run.config.seed);
  } else if (ends_with(path, ".vxa")) {
    VxaRobot vxa = read_vxa_file(path);
    src.robot = std::move(vxa.robot);
    src.physics = vxa.physics;
    src.warnings = std::move(vxa.warnings);
    src.label = src.robot.name;
  } else if (ends_with(path, ".json")) {
    RobotFile file = read_robot_file(path);
    src.robot = std::move(file.robot);
    src.physics = file.physics;
    src.label = src.robot.name.empty() ? path : src.robot.name;
  } else {
    throw InputError(path +
                     ": expected a robot (.json, .vxa), a results file or a recorded life (.h5)");
  }
  return src;
}

std::shared_ptr<const Model> compile_life_model(const LifeSource& source) {
  PhysicsDef def = source.physics;
  def.record_fps = 0;  // frames are captured at the requested times
  return std::make_shared<const Model>(compile(source.robot, def));
}

void simulate_frames(const LifeSource& source, const Model& model, const std::vector<double>& times,
                     const std::function<bool(LifeFrame&&)>& sink,
                     const std::function<void(double)>& progress) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] >= 0 && times[k] <= source.physics.duration + 1e-12))
      throw RenderError(source.path + ": time " + std::to_string(times[k]) +
                        " s is outside the life [0, " + std::to_string(source.physics.duration) +
                        "] s");
    if (k > 0 && times[k] < times[k - 1])
      throw RenderError("simulate_frames: times must be ascending");
  }
  Simulator sim(model);
  const State& s = sim.state();
  // Frames at or after the settle time wait here until the simulation has settled (it
  // settles on the first step past the settle time), so each goes out with the centre of
  // mass the finished life would report.
  std::deque<Frame> waiting;
  bool stopped = false;
  auto hand_over = [&](bool finished) {
    while (!stopped && !waiting.empty() &&
           (finished || s.settled || waiting.front().time < model.def.settle_time)) {
      LifeFrame f;
      f.frame = std::move(waiting.front());
      waiting.pop_front();
      f.settled = s.settled;
      f.com_settled = s.settled ? s.com_settled : Eigen::Vector3d::Zero();
      stopped = !sink(std::move(f));
    }
  };
  const double end = times.empty() ? 0 : times.back();
  double next_report = 0;
  for (double t : times) {
    while (s.time < t && s.status == SimStatus::kRunning) {
      sim.step();
      if (!waiting.empty()) hand_over(false);
      if (stopped) return;
      if (progress && end > 0 && s.time >= next_report) {
        progress(std::min(1.0, s.time / end));
        next_report = s.time + end / 100;
      }
    }
    if (s.status != SimStatus::kRunning) {
      hand_over(true);
      throw RenderError(source.path + ": the simulation went unstable at t = " +
                        std::to_string(s.time) + " s (" + s.failure + ")");
    }
    waiting.push_back(capture(s));
    hand_over(false);
    if (stopped) return;
  }
  hand_over(true);
  if (progress && !stopped) progress(1.0);
}

Life simulate_life(const LifeSource& source, const std::vector<double>& times,
                   const std::function<void(double)>& progress) {
  Life life;
  life.model = compile_life_model(source);
  life.frames.reserve(times.size());
  simulate_frames(
      source, *life.model, times,
      [&](LifeFrame&& f) {
        // Every frame leaves with the final settling state but the ones before settling,
        // which leave with "not settled" and do not use it.
        life.settled = f.settled;
        life.com_settled = f.com_settled;
        life.frames.push_back(std::move(f.frame));
        return true;
      },
      progress);
  return life;
}

Eigen::Vector3d center_of_mass(const Frame& frame) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : frame.pos) sum += p;
  return frame.pos.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(frame.pos.size()));
}

double displacement_so_far(const Life& life, const Frame& frame) {
  const Model& m = *life.model;
  if (!life.settled || frame.time < m.def.settle_time) return 0;
  Eigen::Vector3d d = (center_of_mass(frame) - life.com_settled) / m.size;
  if (m.def.fitness == FitnessMode::kXY) d.z() = 0;
  return d.norm();
}

}  // namespace plastivox::render
