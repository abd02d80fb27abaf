#include "test_support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cfenv>
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plastivox/io/robot_file.hpp"
#include "plastivox/task.hpp"

namespace plastivox::testing {

RobotDef block(int nx, int ny, int nz, double E, double voxel_size) {
  RobotDef r = make_empty_robot(nx, ny, nz, voxel_size);
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = E;
  }
  return r;
}

PhysicsDef passive_physics() {
  PhysicsDef d;
  d.act_amplitude = 0;
  d.self_collision = false;
  d.e_min = 1e4;
  d.e_max = 1e12;
  return d;
}

PhysicsDef with_environment(PhysicsDef def, const std::string& environment) {
  apply_physics_json("{\"environment\": " + environment + "}", "test", def);
  return def;
}

double task_score_after(const Model& m, const State& first, const std::vector<State>& states) {
  State seen = first;
  carry_task_values(make_initial_state(m), seen);
  see_task(m, seen);
  for (State s : states) {
    carry_task_values(seen, s);
    see_task(m, s);
    seen = s;
  }
  return task_score(m, seen, SimResult{});
}

void run_until(Simulator& sim, double t) {
  while (sim.state().time < t && sim.state().status == SimStatus::kRunning) sim.step();
}

long self_contacts_of(const Model& m) {
  Simulator sim(m);
  const State& s = sim.state();
  long touching = 0;
  while (s.status == SimStatus::kRunning) {
    sim.step();
    for (int i = 0; i < m.n; ++i)
      for (int j = i + 1; j < m.n; ++j) {
        const double contact = 0.5 * m.def.contact_diameter * (s.size[i] + s.size[j]);
        const std::vector<int>& near = m.near_voxels[i];
        touching += m.surface[i] && m.surface[j] &&
                    !std::binary_search(near.begin(), near.end(), j) &&
                    (s.pos[j] - s.pos[i]).squaredNorm() < contact * contact;
      }
  }
  return touching;
}

std::string data_dir() {
  return PLASTIVOX_TEST_DATA_DIR;
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Output shell(const std::string& command_line) {
  Output o;
  FILE* p = popen(command_line.c_str(), "r");
  if (!p) return o;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) o.out.append(buf, n);
  const int st = pclose(p);
  o.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return o;
}

std::string headless_chromium(const std::string& profile_dir) {
  const Output which = shell("command -v chromium 2>/dev/null");
  if (which.status != 0 || which.out.empty()) return "";
  return which.out.substr(0, which.out.find('\n')) +
         " --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
         "--host-resolver-rules='MAP * ~NOTFOUND' --disable-background-networking "
         "--disable-component-update --disable-sync --no-first-run --user-data-dir=" +
         profile_dir + " ";
}

std::string dom_attribute(const std::string& dom, const std::string& name) {
  // Built by appending, not with operator+ or replace: GCC 12 at -O3 reports a false
  // -Wrestrict on those here.
  std::string open = " ";
  open += name;
  open += "=\"";
  const size_t at = dom.find(open);
  if (at == std::string::npos) return "";
  std::string v;
  for (size_t i = at + open.size(); i < dom.size() && dom[i] != '"';) {
    if (dom.compare(i, 6, "&quot;") == 0) {
      v += '"';
      i += 6;
    } else if (dom.compare(i, 5, "&amp;") == 0) {
      v += '&';
      i += 5;
    } else {
      v += dom[i++];
    }
  }
  return v;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

Output cli(const std::string& args) {
  return shell(std::string(PLASTIVOX_CLI) + " " + args + " 2>&1");
}

nlohmann::json cli_json(const std::string& args) {
  const Output o = cli(args);
  EXPECT_EQ(o.status, 0) << args << ": " << o.out;
  return o.status == 0 ? nlohmann::json::parse(o.out) : nlohmann::json();
}

void ScratchDirTest::SetUp() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  dir_ = std::filesystem::temp_directory_path() /
         ("plastivox_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
          std::to_string(::getpid()));
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

void ScratchDirTest::TearDown() {
  std::filesystem::remove_all(dir_);
}

namespace {
// Trap invalid operations (NaN production) in every test binary.
struct TrapFpe {
  TrapFpe() { feenableexcept(FE_INVALID); }
} trap_fpe;
}  // namespace

}  // namespace plastivox::testing

// LeakSanitizer (the sanitizer CI job) reads this hook: Mesa's libOSMesa keeps a few small
// allocations per context past OSMesaDestroyContext; they are the library's, not ours.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n";
}
