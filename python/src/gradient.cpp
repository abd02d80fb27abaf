// Gradients of a life for Python (docs/gradients.md): plastivox.gradient, and
// plastivox.gradient_of for a loss of recorded states. The C++ library engine/grad computes
// them; the life runs with the GIL released.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::py {
namespace {

// What `wrt` may name: the Robot's own arrays (act_amplitude: its own amplitudes; act_scale:
// its actuation scales), the physics' global amplitude ("amplitude"), the Robot's controller
// (its weights) and its initial state.
constexpr const char* kWrt[] = {"stiffness",
                                "phase",
                                "dev_rate",
                                "act_amplitude",
                                "act_scale",
                                "amplitude",
                                "controller",
                                "initial_position",
                                "initial_velocity",
                                "initial_orientation",
                                "initial_angular_velocity"};

void check_wrt(const PyRobot& robot, const std::vector<std::string>& wrt) {
  for (const std::string& name : wrt) {
    bool known = false;
    for (const char* k : kWrt) known = known || name == k;
    if (!known)
      throw std::invalid_argument("wrt: no parameter is called '" + name +
                                  "' (stiffness, phase, dev_rate, act_amplitude, act_scale, "
                                  "amplitude, controller, initial_position, initial_velocity, "
                                  "initial_orientation, initial_angular_velocity)");
    if (name == "act_amplitude" && robot.def.act_amplitude.empty())
      throw std::invalid_argument(
          "wrt: 'act_amplitude': the robot has no amplitudes of its own (Robot.act_amplitude is "
          "None: its voxels actuate by physics act_amplitude x xi(E)); 'amplitude' is that one");
  }
}

// The derivatives `wrt` names: per site (a flat array over the lattice's sites, 0 where no
// voxel is; the Python layer shapes it like the Robot's arrays), a float for "amplitude", the
// weights in their order, and per robot voxel x, y, z (x, y, z, w) for the initial state.
pyb::dict derivatives(const PyRobot& robot, const Model& model, const grad::Gradient& g,
                      const std::vector<std::string>& wrt) {
  const auto on_sites = [&](const std::vector<double>& per_voxel) {
    std::vector<double> sites(robot.def.present.size(), 0.0);
    for (int i = 0; i < model.robot_n; ++i) sites[model.site[i]] = per_voxel[i];
    return to_array(sites);
  };
  const auto per_voxel = [&](const std::vector<double>& xyz, pyb::ssize_t width) {
    pyb::array_t<double> a({static_cast<pyb::ssize_t>(model.robot_n), width});
    std::copy(xyz.begin(), xyz.end(), a.mutable_data());
    return a;
  };
  pyb::dict out;
  for (const std::string& name : wrt) {
    if (name == "stiffness") out[name.c_str()] = on_sites(g.stiffness);
    if (name == "phase") out[name.c_str()] = on_sites(g.phase);
    if (name == "dev_rate") out[name.c_str()] = on_sites(g.dev_rate);
    // Without an act_scale array, d / d act_scale is at 1, the value the robot's voxels have.
    if (name == "act_amplitude")
      out[name.c_str()] = on_sites(grad::gain_factor_derivative(g, model, robot.def.act_scale));
    if (name == "act_scale")
      out[name.c_str()] = on_sites(grad::gain_factor_derivative(g, model, robot.def.act_amplitude));
    if (name == "amplitude") out[name.c_str()] = g.amplitude;
    if (name == "controller") out[name.c_str()] = to_array(g.controller_weights);
    if (name == "initial_position") out[name.c_str()] = per_voxel(g.initial_position, 3);
    if (name == "initial_velocity") out[name.c_str()] = per_voxel(g.initial_velocity, 3);
    if (name == "initial_orientation") out[name.c_str()] = per_voxel(g.initial_orientation, 4);
    if (name == "initial_angular_velocity")
      out[name.c_str()] = per_voxel(g.initial_angular_velocity, 3);
  }
  return out;
}

// The fitness of the robot's life (as simulate gives it, bit for bit) and, for each name in
// wrt, its derivative: a flat array over the lattice's sites (0 where no voxel is; the Python
// layer shapes it like the Robot's arrays), or a float for "amplitude".
pyb::tuple gradient_one(const PyRobot& robot, const pyb::object& physics_arg,
                        const std::optional<std::string>& treatment,
                        const std::vector<std::string>& wrt, int threads) {
  check_wrt(robot, wrt);
  const PhysicsDef physics = physics_of_call(robot.physics, physics_arg, treatment, std::nullopt);
  for (const std::string& name : wrt)
    if (name == "controller" && robot.def.controller.weights.empty())
      throw std::invalid_argument(
          "wrt: 'controller': the robot's controller is the sine, which has no weights "
          "(Robot.with_controller gives it a network)");
  if (threads < 0)
    throw std::invalid_argument("threads: expected an integer >= 0 (0: all cores), got " +
                                std::to_string(threads));
  grad::Gradient g;
  Model model;
  {
    pyb::gil_scoped_release unlocked;
    model = compile(robot.def, physics, limits_from_environment());
    // The gradient's forward life, judged as simulate judges a life: one that does not count
    // (sank under sinking_invalid, or unstable) scores 0 whatever its parameters, and has no
    // gradient to give.
    grad::GradientOptions options;
    options.threads = threads;
    options.judge = [&physics](SimResult& r) { judge_life(physics, r); };
    g = grad::gradient(model, options);
    if (g.life.status != SimStatus::kFinished)
      throw std::invalid_argument(
          "gradient: the life does not count, so its fitness has no "
          "gradient: " +
          g.life.failure);
  }
  return pyb::make_tuple(g.fitness, derivatives(robot, model, g, wrt));
}

// ---- plastivox.gradient_of: a user's loss of the states at chosen steps ----

// The numpy shape of a State row (as Simulator.state gives it): () for one value, (n, width)
// for a vector per voxel, (count,) otherwise.
std::vector<pyb::ssize_t> row_shape(const StateField& f, const StateFieldBytes& b) {
  if (std::string(f.shape) == "1") return {};
  if (std::string(f.shape).find(" x ") != std::string::npos)
    return {static_cast<pyb::ssize_t>(b.count / b.width), static_cast<pyb::ssize_t>(b.width)};
  return {static_cast<pyb::ssize_t>(b.count)};
}

// The rows a loss reads, and the states recorded at its steps: each row's values at each step,
// one after the other; then the loss's derivatives, shaped alike (empty: none given). The life
// runs once: the steps counted from the end are kept from a ring of the last states, and placed
// once the life is over.
struct Recorded {
  std::vector<size_t> rows;    // indices into kStateFields
  bool every = false;          // every state (steps None)
  std::vector<int64_t> asked;  // the steps as given (negative: from the end)
  std::vector<int64_t> ahead;  // the steps >= 0 asked, increasing: recorded as the life runs
  size_t next = 0;             // the next of them
  std::vector<std::vector<double>> kept;               // their values, one per row
  int64_t tail = 0;                                    // the last states the steps < 0 reach
  std::vector<std::vector<std::vector<double>>> ring;  // [state % tail][row]
  double bytes = 0, limit_bytes = 0;  // kept so far; the recording limit (check_recording_size)
  int64_t limit_mb = 0;
  // The states the loss is handed (increasing), their values and the loss's derivatives.
  std::vector<int64_t> steps;
  std::vector<std::vector<double>> values, derivatives;  // one per row
  // Forward: keep the rows of state s where asked.
  void see(const State& s) {
    const bool wanted = every || (next < ahead.size() && s.steps == ahead[next]);
    for (size_t k = 0; k < rows.size(); ++k) {
      const StateFieldBytes b = kStateFields[rows[k]].bytes(s);
      const double* v = static_cast<const double*>(b.data);
      if (wanted) {
        std::vector<double>& to = every ? values[k] : kept[k];
        to.insert(to.end(), v, v + b.count);
        bytes += 2.0 * static_cast<double>(b.count * sizeof(double));
      }
      if (tail > 0) ring[static_cast<size_t>(s.steps % tail)][k].assign(v, v + b.count);
    }
    if (!wanted) return;
    if (every)
      steps.push_back(s.steps);
    else
      ++next;
    // A life longer than planned (development shortens dt): held to the limit as it runs.
    if (bytes > limit_bytes) check_recording_size(bytes, "steps", limit_mb);
  }
  // Once the life's last state (`last` steps) is known: the steps asked, placed and checked,
  // and their values gathered from those kept and the ring.
  void place(int64_t last) {
    if (every) return;
    for (int64_t k : asked) {
      const int64_t at = k < 0 ? last + 1 + k : k;
      if (at < 0 || at > last)
        throw std::invalid_argument("steps: " + std::to_string(k) +
                                    " is outside the life's states 0.." + std::to_string(last) +
                                    " (-1 the last)");
      steps.push_back(at);
    }
    std::sort(steps.begin(), steps.end());
    steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
    values.assign(rows.size(), {});
    for (int64_t at : steps) {
      const auto j = std::lower_bound(ahead.begin(), ahead.end(), at);
      for (size_t k = 0; k < rows.size(); ++k) {
        if (j != ahead.end() && *j == at) {
          const size_t width = kept[k].size() / ahead.size();
          const auto from = kept[k].begin() + static_cast<ptrdiff_t>(width) * (j - ahead.begin());
          values[k].insert(values[k].end(), from, from + static_cast<ptrdiff_t>(width));
        } else {
          const std::vector<double>& from = ring[static_cast<size_t>(at % tail)][k];
          values[k].insert(values[k].end(), from.begin(), from.end());
        }
      }
    }
  }
};

// A derivative handed over from Python as float64 values, shaped `shape`; else
// std::invalid_argument: `what` then the shape it must have.
std::vector<double> shaped_values(const pyb::handle& given, const std::vector<pyb::ssize_t>& shape,
                                  const std::string& what) {
  const auto a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(given);
  if (!a || a.ndim() != static_cast<pyb::ssize_t>(shape.size()) ||
      !std::equal(shape.begin(), shape.end(), a.shape()))
    throw std::invalid_argument(what + std::string(pyb::str(pyb::tuple(pyb::cast(shape)))));
  return std::vector<double>(a.data(), a.data() + a.size());
}

// Adds to d the derivatives given at state s, if s is one of `steps` (increasing): given[k]
// holds a row of kStateFields[rows[k]] per step (empty: none given). False when s is not.
bool add_given(const std::vector<int64_t>& steps, const std::vector<size_t>& rows,
               const std::vector<std::vector<double>>& given, const State& s,
               std::vector<std::vector<double>>& d) {
  const auto at = std::lower_bound(steps.begin(), steps.end(), s.steps);
  if (at == steps.end() || *at != s.steps) return false;
  for (size_t k = 0; k < rows.size(); ++k) {
    if (given[k].empty()) continue;
    std::vector<double>& row = d[rows[k]];
    const double* from = given[k].data() + static_cast<size_t>(at - steps.begin()) * row.size();
    for (size_t j = 0; j < row.size(); ++j) row[j] += from[j];
  }
  return true;
}

// The value of the user's loss of the recorded states, and its derivatives kept: `loss(states)`
// returns (value, {name: d value / d states[name]}).
double call_loss(const pyb::object& loss, Recorded& rec, const State& shape_of) {
  pyb::gil_scoped_acquire locked;
  pyb::dict states;
  std::vector<std::vector<pyb::ssize_t>> shapes;
  for (size_t k = 0; k < rec.rows.size(); ++k) {
    const StateField& f = kStateFields[rec.rows[k]];
    std::vector<pyb::ssize_t> shape = row_shape(f, f.bytes(shape_of));
    shape.insert(shape.begin(), static_cast<pyb::ssize_t>(rec.steps.size()));
    pyb::array_t<double> a(shape);
    std::copy(rec.values[k].begin(), rec.values[k].end(), a.mutable_data());
    states[f.name] = a;
    shapes.push_back(shape);
  }
  pyb::array_t<int64_t> steps(static_cast<pyb::ssize_t>(rec.steps.size()));
  std::copy(rec.steps.begin(), rec.steps.end(), steps.mutable_data());
  states["steps"] = steps;
  const pyb::object out = loss(states);
  if (!pyb::isinstance<pyb::tuple>(out) || pyb::len(out) != 2 ||
      !pyb::isinstance<pyb::dict>(out.cast<pyb::tuple>()[1]))
    throw pyb::type_error("loss: must return (value, {field: derivative}), got " +
                          std::string(pyb::str(out.get_type().attr("__name__"))));
  const pyb::tuple pair = out.cast<pyb::tuple>();
  const double value = pair[0].cast<double>();
  rec.derivatives.assign(rec.rows.size(), {});
  for (const auto& [key, d] : pair[1].cast<pyb::dict>()) {
    const std::string name = pyb::str(key);
    size_t k = 0;
    while (k < rec.rows.size() && name != kStateFields[rec.rows[k]].name) ++k;
    if (k == rec.rows.size())
      throw std::invalid_argument("loss: a derivative of '" + name +
                                  "', which is not among the fields recorded");
    rec.derivatives[k] = shaped_values(
        d, shapes[k],
        "loss: the derivative of '" + name + "' must be shaped like states['" + name + "'] ");
  }
  return value;
}

// The index in kStateFields of the floating-point row `name` (a loss may read it), else
// std::invalid_argument beginning with `what`.
size_t float_row(const std::string& name, const std::string& what) {
  size_t r = 0;
  while (r < kStateFields.size() && name != kStateFields[r].name) ++r;
  if (grad::is_watch(name.c_str())) r = kStateFields.size();  // not kept by the replica
  if (r < kStateFields.size()) {
    static const State empty{};
    const StateFieldBytes b = kStateFields[r].bytes(empty);
    if (b.kind != 'f' || b.value_bytes != sizeof(double)) r = kStateFields.size();
  }
  if (r == kStateFields.size())
    throw std::invalid_argument(what + ": '" + name +
                                "' is not a floating-point row of the state (Simulator."
                                "state_fields; pos, orient, lin_mom, size, stiffness, ...)");
  return r;
}

// gradient_of: the loss of the states at `steps` (every state when empty; negative: from the
// end, -1 the last), its rows `fields`, and its derivative with respect to `wrt`.
pyb::tuple gradient_of_one(const PyRobot& robot, const pyb::object& physics_arg,
                           const std::optional<std::string>& treatment, const pyb::object& loss,
                           const std::optional<std::vector<int64_t>>& steps,
                           const std::vector<std::string>& fields,
                           const std::vector<std::string>& wrt) {
  check_wrt(robot, wrt);
  Recorded rec;
  for (const std::string& name : fields) {
    const size_t r = float_row(name, "fields");
    if (std::find(rec.rows.begin(), rec.rows.end(), r) == rec.rows.end()) rec.rows.push_back(r);
  }
  const PhysicsDef physics = physics_of_call(robot.physics, physics_arg, treatment, std::nullopt);
  grad::Gradient g;
  Model model;
  {
    pyb::gil_scoped_release unlocked;
    const Limits limits = limits_from_environment();
    model = compile(robot.def, physics, limits);
    // The steps >= 0 are recorded as the life runs; those counted from the end (its length
    // is known once it is over) from a ring of the last states. The life is the gradient's
    // own forward pass: simulated once.
    const State initial = make_initial_state(model);
    double state_bytes = 0;
    for (size_t row : rec.rows)
      state_bytes +=
          2.0 * static_cast<double>(kStateFields[row].bytes(initial).count * sizeof(double));
    rec.every = !steps;
    double planned = 0;  // states the recording will hold
    if (steps) {
      rec.asked = *steps;
      for (int64_t k : *steps) {
        if (k >= 0)
          rec.ahead.push_back(k);
        else
          rec.tail = std::max(rec.tail, -k);
      }
      std::sort(rec.ahead.begin(), rec.ahead.end());
      rec.ahead.erase(std::unique(rec.ahead.begin(), rec.ahead.end()), rec.ahead.end());
      planned = static_cast<double>(rec.ahead.size() + 2 * rec.tail);  // the ring, its copies
    } else {
      planned = std::ceil(model.def.duration / initial.dt) + 2;  // grad::plan's estimate
    }
    check_recording_size(state_bytes * planned, "steps", limits.recording_mb);
    rec.limit_mb = limits.recording_mb;
    rec.limit_bytes = static_cast<double>(limits.recording_mb) * (1 << 20);
    rec.kept.assign(rec.rows.size(), {});
    rec.ring.assign(static_cast<size_t>(rec.tail),
                    std::vector<std::vector<double>>(rec.rows.size()));
    rec.values.assign(rec.rows.size(), {});
    grad::TrajectoryLoss user;
    user.see = [&rec](const State& s) { rec.see(s); };
    user.value = [&](const State& final) {
      rec.place(final.steps);
      return call_loss(loss, rec, final);
    };
    user.adjoint = [&rec](const State& s, std::vector<std::vector<double>>& d) {
      return add_given(rec.steps, rec.rows, rec.derivatives, s, d);
    };
    // The life as simulate judges it: one that does not count has no gradient.
    grad::GradientOptions options;
    options.judge = [&physics](SimResult& r) { judge_life(physics, r); };
    g = grad::gradient_of(model, user, options);
    if (g.life.status != SimStatus::kFinished)
      throw std::invalid_argument("gradient_of: the life does not count, so it has no gradient: " +
                                  g.life.failure);
  }
  return pyb::make_tuple(g.fitness, derivatives(robot, model, g, wrt));
}

// Simulator.backward: the derivatives of a loss of one's own with respect to the states the
// Simulator's life passed through (`derivatives`: {field: array (len(steps), *row shape)};
// `steps`: the states', increasing, negative from the present one, -1 it; none: every state
// 0..steps), carried back to `wrt`. The backward pass recomputes the life from its start, as
// gradient_of does: its forward runs the same model the same number of steps, and must reach
// the Simulator's present state bit for bit (else the life was steered: refused).
pyb::dict backward_of_life(const Simulator& sim, const PyRobot& robot, const pyb::dict& given,
                           const std::optional<std::vector<int64_t>>& steps_arg,
                           const std::vector<std::string>& wrt) {
  check_wrt(robot, wrt);
  const State& now = sim.state();
  const Model& model = sim.model();
  if (now.status == SimStatus::kUnstable)
    throw std::invalid_argument("backward: the life went unstable (" + now.failure +
                                "), so it has no gradient");
  if (now.steps == 0)
    throw std::invalid_argument("backward: the Simulator has not stepped yet (steps is 0)");
  std::vector<int64_t> steps;
  if (steps_arg) {
    for (const int64_t k : *steps_arg) {
      const int64_t at = k < 0 ? now.steps + 1 + k : k;
      if (at < 0 || at > now.steps)
        throw std::invalid_argument("steps: " + std::to_string(k) +
                                    " is outside the life's states 0.." +
                                    std::to_string(now.steps) + " (-1 the present one)");
      if (!steps.empty() && at <= steps.back())
        throw std::invalid_argument("steps: the states must increase, as the derivatives' rows do");
      steps.push_back(at);
    }
  } else {
    for (int64_t k = 0; k <= now.steps; ++k) steps.push_back(k);
  }
  // Each derivative as rows of float64, checked against its field's shape.
  std::vector<size_t> rows;
  std::vector<std::vector<double>> d_rows;
  for (const auto& [key, value] : given) {
    const std::string name = pyb::str(key);
    const size_t r = float_row(name, "derivatives");
    const StateField& f = kStateFields[r];
    std::vector<pyb::ssize_t> shape = row_shape(f, f.bytes(now));
    shape.insert(shape.begin(), static_cast<pyb::ssize_t>(steps.size()));
    if (std::find(rows.begin(), rows.end(), r) != rows.end())
      throw std::invalid_argument("derivatives: '" + name + "' given twice");
    rows.push_back(r);
    d_rows.push_back(shaped_values(value, shape, "derivatives: '" + name + "' must be shaped "));
  }
  const std::invalid_argument steered(
      "backward: this Simulator's life is not its robot's own from t = 0 (set_actuation, "
      "set_controller or restore_state steered it): the backward pass recomputes the life "
      "from its start, so it needs a life that step(), step1() and step2() alone made "
      "(a new Simulator starts one afresh)");
  grad::Gradient g;
  {
    pyb::gil_scoped_release unlocked;
    grad::TrajectoryLoss user;
    user.see = [](const State&) {};
    // Called with the recomputed life's last state before the reverse sweeps: a life that does
    // not reach the Simulator's present state is refused before they run.
    user.value = [&](const State& last) {
      if (last.steps != now.steps || state_hash(last) != state_hash(now)) throw steered;
      return 0.0;  // the loss's value is the caller's
    };
    user.adjoint = [&](const State& s, std::vector<std::vector<double>>& d) {
      return add_given(steps, rows, d_rows, s, d);
    };
    grad::GradientOptions options;
    options.steps = now.steps;
    // Judged as it is: a recomputation that went unstable returns without a backward pass.
    options.judge = [](SimResult&) {};
    g = grad::gradient_of(model, user, options);
  }
  // The Simulator's own life did not go unstable (refused above): this one was not it.
  if (g.life.status == SimStatus::kUnstable) throw steered;
  return derivatives(robot, model, g, wrt);
}

}  // namespace

void bind_backward(const pyb::object& simulator_class, UseSimulator use) {
  const pyb::handle cls = simulator_class;
  cls.attr("backward") = pyb::cpp_function(
      [use](const pyb::handle& self, const PyRobot& robot, const pyb::dict& given,
            const std::optional<std::vector<int64_t>>& steps, const std::vector<std::string>& wrt) {
        pyb::dict out;
        use(self, [&](Simulator& sim) { out = backward_of_life(sim, robot, given, steps, wrt); });
        return out;
      },
      pyb::name("backward"), pyb::is_method(cls), pyb::arg("robot"), pyb::arg("derivatives"),
      pyb::arg("steps"), pyb::arg("wrt"));
}

void bind_gradient(pyb::module_& m) {
  m.def("gradient", &gradient_one, pyb::arg("robot"), pyb::arg("physics"), pyb::arg("treatment"),
        pyb::arg("wrt"), pyb::arg("threads"));
  m.def("gradient_of", &gradient_of_one, pyb::arg("robot"), pyb::arg("physics"),
        pyb::arg("treatment"), pyb::arg("loss"), pyb::arg("steps"), pyb::arg("fields"),
        pyb::arg("wrt"));
}

}  // namespace plastivox::py
