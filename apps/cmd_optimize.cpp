// plastivox optimize: gradient ascent of a robot's fitness through its life (docs/gradients.md,
// "plastivox optimize"). Each step compiles the robot, takes grad::gradient() of its life,
// judges that life's forward pass as `simulate` judges a life (one life a step, not two) and
// moves the chosen arrays; the best robot seen is written with the robot writer, and a
// JSON-lines log keeps every step's fitness.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "plastivox/base/hash.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox/io/resolve_physics.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/io/vxa.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox_version.hpp"

namespace plastivox::cli {
namespace {

using nlohmann::json;

// What `--wrt` may name: the robot's arrays (act_amplitude: its own amplitudes; act_scale: its
// actuation scales), its controller's weights (RobotDef's and Python's Robot's own attribute
// names) and the physics' global amplitude, "amplitude" (as plastivox.gradient names it).
constexpr const char* kWrt[] = {"stiffness", "phase",     "dev_rate",  "act_amplitude",
                                "act_scale", "amplitude", "controller"};

// The largest amplitude the robot format and the physics allow: [0, 0.9).
const double kAmplitudeTop = std::nextafter(0.9, 0.0);

// Adam's moments for one array, per lattice site or weight.
struct Moments {
  std::vector<double> m, v;
};

struct Settings {
  std::string method = "adam";
  double lr = 0.01;
  double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;  // Adam's usual constants
};

// The robot's array called `name`.
std::vector<double>& array_of(RobotDef& r, const std::string& name) {
  if (name == "stiffness") return r.stiffness;
  if (name == "phase") return r.phase;
  if (name == "controller") return r.controller.weights;
  if (name == "act_amplitude") return r.act_amplitude;
  if (name == "act_scale") return r.act_scale;
  return r.dev_rate;
}

// One optimised coordinate: where it sits in its array (a lattice site, or a weight's index)
// and d fitness / d it.
struct Coordinate {
  size_t at;
  double slope;
};

// The coordinates of `name`: per cycle of phase, per 1/s of rate, per unit of a weight, an
// amplitude or an actuation scale, and per unit of log E for stiffness (a step of lr moves E by
// about lr of itself, and a modulus spans six decades: the same lr serves every voxel).
std::vector<Coordinate> coordinates(const std::string& name, const grad::Gradient& g,
                                    const Model& m, const RobotDef& robot) {
  std::vector<Coordinate> out;
  if (name == "amplitude") return {{0, g.amplitude}};
  if (name == "controller") {
    for (size_t k = 0; k < g.controller_weights.size(); ++k)
      out.push_back({k, g.controller_weights[k]});
    return out;
  }
  // A voxel's gain is its own amplitude (1 under the paper's rule) times its act_scale.
  const std::vector<double> gain =
      name == "act_amplitude" ? grad::gain_factor_derivative(g, m, robot.act_scale)
      : name == "act_scale"   ? grad::gain_factor_derivative(g, m, robot.act_amplitude)
                              : std::vector<double>{};
  for (int i = 0; i < m.robot_n; ++i) {
    const double d = name == "stiffness" ? g.stiffness[i] * m.e0[i]
                     : name == "phase"   ? g.phase[i]
                     : !gain.empty()     ? gain[i]
                                         : g.dev_rate[i];
    out.push_back({static_cast<size_t>(m.site[i]), d});
  }
  return out;
}

// Moves one value by `step` in its coordinate and keeps it valid for the robot file and the
// engine: E in [e_min, e_max] (compile() clamps there, so beyond it the fitness is flat), a
// phase wrapped into [-0.5, 0.5] cycles when it leaves it (the sine has period 1), an
// amplitude held to [0, 0.9) (the robot format's and the physics' range), an actuation scale
// to [0, 1] (the robot format's), a rate or a weight anything finite.
double moved(const std::string& name, double value, double step, const PhysicsDef& physics) {
  if (name == "act_amplitude" || name == "amplitude")
    return std::clamp(value + step, 0.0, kAmplitudeTop);
  if (name == "act_scale") return std::clamp(value + step, 0.0, 1.0);
  if (name == "stiffness")
    return std::clamp(std::exp(std::log(value) + step), physics.e_min, physics.e_max);
  if (name == "phase") {
    const double p = value + step;
    return p > 0.5 || p < -0.5 ? p - std::round(p) : p;
  }
  return value + step;
}

// One step of the method on every array `wrt` names, and the physics' amplitude (t: the
// step's number from 1, for Adam's bias correction); returns the gradient's norm per name, for
// the log.
json ascend(RobotDef& robot, PhysicsDef& physics, const std::vector<std::string>& wrt,
            std::vector<Moments>& moments, const Settings& settings, int t, const grad::Gradient& g,
            const Model& model) {
  json norms;
  // Every derivative is read at the robot the gradient was taken of: moving the amplitudes
  // first must not change the scales' chain rule, nor the reverse.
  const RobotDef at = robot;
  for (size_t p = 0; p < wrt.size(); ++p) {
    std::vector<double> global = {physics.act_amplitude};
    std::vector<double>& values = wrt[p] == "amplitude" ? global : array_of(robot, wrt[p]);
    Moments& mo = moments[p];
    double norm2 = 0;
    for (const auto& [s, d] : coordinates(wrt[p], g, model, at)) {
      norm2 += d * d;
      double step = settings.lr * d;
      if (settings.method == "adam") {
        mo.m[s] = settings.beta1 * mo.m[s] + (1 - settings.beta1) * d;
        mo.v[s] = settings.beta2 * mo.v[s] + (1 - settings.beta2) * d * d;
        const double mh = mo.m[s] / (1 - std::pow(settings.beta1, t));
        const double vh = mo.v[s] / (1 - std::pow(settings.beta2, t));
        step = settings.lr * mh / (std::sqrt(vh) + settings.eps);
      }
      values[s] = moved(wrt[p], values[s], step, physics);
    }
    if (wrt[p] == "amplitude") physics.act_amplitude = global[0];
    norms[wrt[p]] = std::sqrt(norm2);
  }
  return norms;
}

// The life as `simulate` judges it: its fitness, or why it does not count.
struct Judged {
  double fitness = 0;
  int64_t steps = 0;  // the life's engine steps (the gradient's forward and recomputation: as many)
  std::string failure;  // "" when the life counts
};
Judged judged(const SimResult& r) {
  Judged out;
  out.fitness = r.fitness;
  out.steps = r.steps;
  if (r.status != SimStatus::kFinished)
    out.failure = std::string(r.sank ? "life invalid: " : "simulation unstable: ") + r.failure;
  return out;
}
Judged judged_life(const Model& model, const PhysicsDef& physics) {
  SimResult r = simulate(model);
  judge_life(physics, r);
  return judged(r);
}

std::string g6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// The log's first line: what was asked, of what, with which physics, by which build.
json log_header(const std::string& source, const std::vector<std::string>& wrt, const Settings& s,
                int steps, const PhysicsDef& physics, const std::string& out) {
  json h = {{"format", "plastivox-optimize-log"},
            {"version", 1},
            {"robot", source},
            {"out", out},
            {"wrt", wrt},
            {"method", s.method},
            {"lr", s.lr},
            {"steps", steps},
            {"physics", json::parse(physics_to_json(physics))},
            {"seed", nullptr}};  // gradient ascent draws nothing: the inputs fix the run
  if (s.method == "adam") h["adam"] = {{"beta1", s.beta1}, {"beta2", s.beta2}, {"eps", s.eps}};
  json prov;
  const Provenance here = current_provenance(1);
  for_each_field(here, [&](const char* name, const auto& v) { prov[name] = v; });
  h["provenance"] = prov;
  return h;
}

}  // namespace

int cmd_optimize(const Args& in) {
  Args args = in;
  const std::string wrt_text = take_option(args, "--wrt", "phase,stiffness");
  const std::string method = take_option(args, "--method", "adam");
  const std::string steps_text = take_option(args, "--steps", "10");
  const std::string lr_text = take_option(args, "--lr", "0.01");
  const std::string out = take_option(args, "--out", "");
  std::string log_path = take_option(args, "--log", "");
  const std::string memory_text = take_option(args, "--memory-limit", "2048");
  const std::string threads_text = take_option(args, "--threads", "0");
  const std::string treatment = take_option(args, "--treatment", "");
  const std::string preset = take_option(args, "--preset", "");
  const std::string duration = take_option(args, "--duration", "");
  const std::string overrides = take_option(args, "--physics", "");
  reject_unknown_options(args);
  if (args.size() != 1)
    throw UsageError{"expected one robot file: plastivox optimize ROBOT --out OPTIMISED.json"};
  if (out.empty()) throw UsageError{"--out ROBOT.json (or ROBOT.vxa) is required"};
  if (!out.ends_with(".json") && !out.ends_with(".vxa"))
    throw UsageError{"--out must end in .json or .vxa, got '" + out + "'"};
  if (log_path.empty()) log_path = out.substr(0, out.rfind('.')) + ".log.jsonl";
  std::vector<std::string> wrt;
  for (size_t at = 0; at <= wrt_text.size();) {
    const size_t comma = std::min(wrt_text.find(',', at), wrt_text.size());
    const std::string name = wrt_text.substr(at, comma - at);
    bool known = false;
    for (const char* k : kWrt) known = known || name == k;
    if (!known)
      throw UsageError{"--wrt: no parameter is called '" + name +
                       "' (stiffness, phase, dev_rate, act_amplitude, act_scale, amplitude, "
                       "controller)"};
    for (const std::string& w : wrt)
      if (w == name) throw UsageError{"--wrt names '" + name + "' twice"};
    wrt.push_back(name);
    at = comma + 1;
  }
  Settings settings;
  settings.method = method;
  if (method != "adam" && method != "sgd")
    throw UsageError{"--method expects adam or sgd, got '" + method + "'"};
  const int steps = parse_count(steps_text, "--steps");
  if (steps < 1) throw UsageError{"--steps must be at least 1"};
  if (!read_number(lr_text, settings.lr) || !(settings.lr > 0))
    throw UsageError{"--lr must be a number > 0, got '" + lr_text + "'"};
  double memory_mb = 0;
  if (!read_number(memory_text, memory_mb) || !(memory_mb > 0))
    throw UsageError{"--memory-limit must be a number of MB > 0, got '" + memory_text + "'"};
  const int threads = parse_count(threads_text, "--threads");
  PhysicsRequest request;
  request.preset = preset;
  request.fields = overrides;
  request.where = overrides.empty() ? args[0] : "--physics";
  const auto checked = [](const std::string& option, const auto& parse) {
    try {
      return parse();
    } catch (const std::invalid_argument& e) {
      throw UsageError{option + ": " + e.what()};
    }
  };
  if (!preset.empty()) checked("--preset", [&] { return physics_preset(preset); });
  if (!treatment.empty())
    request.treatment = checked("--treatment", [&] { return parse_treatment(treatment); });
  if (!duration.empty()) {
    double d = 0;
    if (!read_number(duration, d) || !(d >= 0))
      throw UsageError{"--duration must be a number of seconds >= 0, got '" + duration + "'"};
    request.duration = d;
  }

  // The robot and its physics, by simulate's rule (docs/robot-format.md).
  const std::string source = args[0];
  LoadedRobot file = load_robot(source);
  for (const std::string& w : file.warnings)
    std::fprintf(stderr, "plastivox optimize: warning: %s\n", w.c_str());
  RobotDef robot = std::move(file.robot);
  PhysicsDef physics = resolve_physics(file.physics, request);  // --wrt amplitude moves it
  const Limits limits = limits_from_environment();
  const auto compiled = [&](const RobotDef& r) {
    try {
      return compile(r, physics, limits);
    } catch (const std::invalid_argument& e) {
      throw InputError(source + ": " + e.what());
    }
  };
  // Refused before anything runs: a life whose gradient is not built, or that would need more
  // memory than --memory-limit (the plan of the first life; later lives are planned again).
  grad::GradientOptions options;
  options.memory_limit = memory_mb * 1e6;
  options.threads = threads;
  options.judge = [&physics](SimResult& r) { judge_life(physics, r); };
  {
    const Model model = compiled(robot);
    try {
      grad::plan(model, options);
    } catch (const std::invalid_argument& e) {
      throw InputError(source + ": " + e.what() + " (--memory-limit)");
    }
    for (const std::string& name : wrt)
      if (name == "dev_rate" && physics.treatment == Treatment::kNone)
        throw UsageError{
            "--wrt dev_rate: the life has no development (treatment none), so the rates "
            "change nothing; give --treatment"};
    for (const std::string& name : wrt)
      if (name == "controller" && robot.controller.weights.empty())
        throw UsageError{
            "--wrt controller: the robot's controller is the sine, which has no weights "
            "(docs/control.md gives a robot a network)"};
    for (const std::string& name : wrt) {
      if (name == "act_amplitude" && robot.act_amplitude.empty())
        throw UsageError{
            "--wrt act_amplitude: the robot has no amplitudes of its own (its voxels actuate by "
            "physics act_amplitude x xi(E)); --wrt amplitude moves that one"};
      if (name == "act_scale" && out.ends_with(".vxa"))
        throw UsageError{
            "--wrt act_scale: a .vxa file cannot hold per-voxel actuation scales; give --out "
            "a .json"};
      if (name == "amplitude" && !robot.act_amplitude.empty())
        throw UsageError{
            "--wrt amplitude: the robot gives its own amplitudes, which do not read physics "
            "act_amplitude; --wrt act_amplitude moves them"};
    }
  }
  // Stiffness starts inside [e_min, e_max], where compile() holds it anyway: the same life.
  for (int s = 0; s < robot.sites(); ++s)
    if (robot.present[s])
      robot.stiffness[s] = std::clamp(robot.stiffness[s], physics.e_min, physics.e_max);
  // A robot without act_scale has 1 at every voxel (the same life, bit for bit: compile()
  // multiplies the gain by 1); --wrt act_scale moves the array it is given, written with it.
  for (const std::string& name : wrt)
    if (name == "act_scale" && robot.act_scale.empty()) robot.act_scale.assign(robot.sites(), 1.0);
  // A .vxa that could not hold the robot (its own amplitudes or scales, a network, a task
  // other than walk, ...) is refused now, not when it is written after the run: the steps move
  // values the format holds, never what it cannot.
  if (out.ends_with(".vxa")) {
    try {
      (void)write_vxa(robot, physics);
    } catch (const std::exception& e) {
      throw UsageError{"--out " + out + ": " + e.what()};
    }
  }

  std::string log_text = log_header(source, wrt, settings, steps, physics, out).dump() + "\n";
  std::vector<Moments> moments(wrt.size());
  for (size_t p = 0; p < wrt.size(); ++p) {
    const size_t size = wrt[p] == "amplitude" ? 1 : array_of(robot, wrt[p]).size();
    moments[p].m.assign(size, 0.0);
    moments[p].v.assign(size, 0.0);
  }
  RobotDef best = robot;
  PhysicsDef best_physics = physics;
  double best_fitness = -HUGE_VAL, first_fitness = 0;
  int best_step = -1;
  std::string stopped;

  // Resumable: after every step, what the next steps need (the arrays --wrt moves, Adam's
  // moments, the best robot so far, the log) is written atomically to OUT.resume.json, and the
  // same command continues from it after a kill, to the same bits; it is removed once OUT is
  // written. What fixes the run (the robot as read, the physics, the settings) is its key:
  // a checkpoint of another run is refused.
  const std::string resume_path = out + ".resume.json";
  Hasher key_hash;
  key_hash.str(robot_to_json(robot, &physics));
  // (--memory-limit can refuse a later step's gradient, which ends the run: in the key.)
  key_hash.str(json({wrt, method, settings.lr, steps, memory_mb}).dump());
  const std::string key = key_hash.finish().hex();
  // Doubles as JSON keeps them exactly (a finite one as a number, which round-trips; an
  // infinity or a NaN, which Adam's moments or a fitness may hold, as a string).
  const auto exact_json = [](const std::vector<double>& v) {
    json a = json::array();
    for (const double x : v) a.push_back(std::isfinite(x) ? json(x) : json(std::to_string(x)));
    return a;
  };
  const auto doubles_of = [](const json& a) {
    std::vector<double> v;
    for (const json& x : a)
      v.push_back(x.is_string() ? std::stod(x.get<std::string>()) : x.get<double>());
    return v;
  };
  // The arrays --wrt moves (the physics' amplitude for "amplitude").
  const auto moved_arrays = [&](RobotDef& r, const PhysicsDef& ph) {
    json a;
    for (const std::string& name : wrt)
      a[name] = exact_json(name == "amplitude" ? std::vector<double>{ph.act_amplitude}
                                               : array_of(r, name));
    return a;
  };
  const auto put_arrays = [&](const json& a, RobotDef& r, PhysicsDef& ph) {
    for (const std::string& name : wrt) {
      const std::vector<double> v = doubles_of(a.at(name));
      if (v.size() != (name == "amplitude" ? 1 : array_of(r, name).size()))
        throw std::invalid_argument("'" + name + "' has the wrong size");
      if (name == "amplitude")
        ph.act_amplitude = v[0];
      else
        array_of(r, name) = v;
    }
  };
  int first_step = 0;
  if (std::filesystem::exists(resume_path)) {
    try {
      const json c = json::parse(read_file_bytes(resume_path));
      if (c.at("format") != "plastivox-optimize-checkpoint" || c.at("key") != key)
        throw UsageError{resume_path +
                         ": the checkpoint of another optimize run (another robot, physics, "
                         "--wrt, --method, --lr or --steps); delete it to start afresh"};
      put_arrays(c.at("robot"), robot, physics);
      put_arrays(c.at("best"), best, best_physics);
      for (size_t p = 0; p < wrt.size(); ++p) {
        const std::vector<double> m = doubles_of(c.at("moments").at(p).at(0));
        const std::vector<double> v = doubles_of(c.at("moments").at(p).at(1));
        if (m.size() != moments[p].m.size() || v.size() != moments[p].v.size())
          throw std::invalid_argument("moments of the wrong size");
        moments[p].m = m, moments[p].v = v;
      }
      best_fitness = doubles_of(c.at("best_fitness")).at(0);
      first_fitness = doubles_of(c.at("first_fitness")).at(0);
      best_step = c.at("best_step");
      log_text = c.at("log");
      first_step = c.at("next");
      if (first_step < 1 || first_step > steps + 1 || best_step < 0 || best_step >= first_step)
        throw std::invalid_argument("its steps are out of range");
    } catch (const UsageError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(resume_path + ": not a readable optimize checkpoint (" + e.what() +
                       "); delete it to start afresh");
    }
    std::fprintf(stderr, "plastivox optimize: resuming at step %d of %d (%s)\n", first_step, steps,
                 resume_path.c_str());
  }
  for (int k = first_step; k <= steps; ++k) {
    const auto started = std::chrono::steady_clock::now();
    const std::clock_t cpu_started = std::clock();  // the process's CPU time (one thread)
    const Model model = compiled(robot);
    // The gradient's forward life is the step's evaluation, judged as simulate judges it (the
    // options' judge). The last robot has no gradient to take, and one refused after its life
    // ran is logged as the life it was: each is simulated alone.
    std::optional<grad::Gradient> g;
    std::string refused;
    if (k < steps) {
      try {
        g = grad::gradient(model, options);
      } catch (const std::exception& e) {
        // Refused (memory, a tape too long: invalid_argument) or a branch not differentiated
        // yet (domain_error): the run stops after this step's line. A replica that left the
        // engine's life (a plain logic_error) is a bug, and propagates.
        // The first life's plan passed; a body that stiffens can still pass --memory-limit as
        // it runs (more steps, so more snapshots, than its initial time step gave).
        if (k == 0 && dynamic_cast<const grad::MemoryLimitError*>(&e))
          throw InputError(source + ": " + e.what() + " (--memory-limit)");
        if (k == 0 || typeid(e) == typeid(std::logic_error)) throw;
        refused = "step " + std::to_string(k) + ": " + e.what();
      }
    }
    const Judged life = g ? judged(g->life) : judged_life(model, physics);
    if (!life.failure.empty()) {
      if (k == 0)
        throw InputError(source +
                         ": the life does not count, so it has no gradient: " + life.failure);
      stopped = "step " + std::to_string(k) + ": " + life.failure;
      log_text += json({{"step", k}, {"fitness", life.fitness}, {"failure", life.failure}}).dump();
      log_text += "\n";
      break;
    }
    json line = {{"step", k}, {"fitness", life.fitness}};
    if (k == 0) first_fitness = life.fitness;
    if (life.fitness > best_fitness)
      best = robot, best_physics = physics, best_fitness = life.fitness, best_step = k;
    if (g) {
      if (g->fitness != life.fitness)  // the same life, bit for bit (docs/gradients.md)
        throw std::logic_error("optimize: the gradient's life scored " + g6(g->fitness) +
                               ", simulate's " + g6(life.fitness));
      line["gradient_norm"] = ascend(robot, physics, wrt, moments, settings, k + 1, *g, model);
    }
    stopped = refused;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    line["seconds"] = seconds;
    line["cpu_seconds"] = static_cast<double>(std::clock() - cpu_started) / CLOCKS_PER_SEC;
    line["life_steps"] = life.steps;
    log_text += line.dump() + "\n";
    write_file_atomic(log_path, log_text);  // a killed run keeps the steps it took
    if (stopped.empty()) {
      json c = {{"format", "plastivox-optimize-checkpoint"},
                {"key", key},
                {"next", k + 1},
                {"robot", moved_arrays(robot, physics)},
                {"best", moved_arrays(best, best_physics)},
                {"best_fitness", exact_json({best_fitness})},
                {"best_step", best_step},
                {"first_fitness", exact_json({first_fitness})},
                {"log", log_text}};
      json& m = c["moments"] = json::array();
      for (const Moments& mo : moments) m.push_back({exact_json(mo.m), exact_json(mo.v)});
      write_file_atomic(resume_path, c.dump());
    }
    std::fprintf(stderr, "plastivox optimize: step %d/%d fitness %s%s (%.1f s)\n", k, steps,
                 g6(life.fitness).c_str(), k < steps ? "" : " (the last robot)", seconds);
    if (!stopped.empty()) break;
  }
  if (!stopped.empty())
    std::fprintf(stderr, "plastivox optimize: warning: stopped at %s; writing the best so far\n",
                 stopped.c_str());

  // The best robot, written, then replayed from the file as `simulate OUT` reads it: the
  // log's last line is what that replay scores.
  std::vector<std::string> warnings;
  save_robot(out, best, best_physics, &warnings);
  for (const std::string& w : warnings)
    std::fprintf(stderr, "plastivox optimize: warning: %s\n", w.c_str());
  LoadedRobot written = load_robot(out);
  const Judged replay =
      judged_life(compile(written.robot, written.physics, limits), written.physics);
  if (replay.fitness != best_fitness)
    std::fprintf(stderr,
                 "plastivox optimize: warning: %s replays to fitness %s, not %s (the file "
                 "format rounds the values; .json keeps them exactly)\n",
                 out.c_str(), g6(replay.fitness).c_str(), g6(best_fitness).c_str());
  json result = {{"written", out}, {"step", best_step}, {"fitness", replay.fitness}};
  if (!stopped.empty()) result["stopped"] = stopped;
  log_text += result.dump() + "\n";
  write_file_atomic(log_path, log_text);
  std::filesystem::remove(resume_path);
  std::printf("wrote %s: fitness %s at step %d of %d (from %s at step 0); log %s\n", out.c_str(),
              g6(replay.fitness).c_str(), best_step, steps, g6(first_fitness).c_str(),
              log_path.c_str());
  return 0;
}

}  // namespace plastivox::cli
