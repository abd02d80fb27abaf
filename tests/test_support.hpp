// Shared helpers for the test suite: tiny robots built inline, quiet physics, named
// tolerances. Every test binary also traps floating-point invalid operations, so a NaN
// fails where it is born (see test_support.cpp).
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json_fwd.hpp>

#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::testing {

// A solid nx*ny*nz block of voxels, all with modulus E, phase 0, no development.
RobotDef block(int nx, int ny, int nz, double E, double voxel_size = 0.01);

// Physics with the GECCO defaults but no actuation, no self-collision and E in [1e4, 1e12]:
// a clean setting for mechanics checks. Duration is left to the test.
PhysicsDef passive_physics();

// def with the environment given as JSON (the text of physics.environment).
PhysicsDef with_environment(PhysicsDef def, const std::string& environment);

// Steps the simulator until its time reaches t (or it goes unstable).
void run_until(Simulator& sim, double t);

// Self-contacts over a whole life, counted step by step: pairs of surface voxels not near in
// the bond graph whose centres are closer than their contact distance (contacts.cpp).
long self_contacts_of(const Model& m);

// The task's running values (task_values, task_layout) of `from` put into `to`, as the task's
// watch would have carried them had the life stepped from `from` to `to`: for feeding a task
// hand-made states.
inline void carry_task_values(const State& from, State& to) {
  to.task_values = from.task_values;
  to.task_layout = from.task_layout;
}
// The task's score (of m's task) of a life that went through `first` and then `states` in
// order and ended on the last: the task's watch sees each, none seen before `first`.
double task_score_after(const Model& m, const State& first, const std::vector<State>& states);

// |actual - expected| <= rel * |expected|, with a message naming both.
inline ::testing::AssertionResult RelNear(double actual, double expected, double rel) {
  if (std::abs(actual - expected) <= rel * std::abs(expected)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "actual " << actual << " vs expected " << expected << " (relative error "
         << (actual - expected) / expected << ", allowed " << rel << ")";
}

std::string data_dir();  // tests/data: sample robots and reference results (README there)

// The whole content of a file, byte for byte; a test failure (and "") if it cannot be read.
std::string file_text(const std::string& path);

// The message of the exception f throws, or "(no error)" when it throws none.
std::string error_of(const std::function<void()>& f);

// Runs a shell command line; out is its standard output (add " 2>&1" to the command for
// standard error too), status its exit status, or 128 + signal if it was killed.
struct Output {
  int status = -1;
  std::string out;
};
Output shell(const std::string& command_line);

// The plastivox program (this build's) run with `args` (words for the shell), its standard
// error merged into the output.
Output cli(const std::string& args);
// The JSON object cli(args) prints; a non-zero exit is a test failure (with the output), and
// the JSON is then null.
nlohmann::json cli_json(const std::string& args);

// Headless Chromium (Debian package chromium) with software WebGL (SwiftShader) and every
// host name unresolvable, as with the network off: the program and its flags, with a fresh
// profile in `profile_dir`, ready for more flags and a URL. "" when chromium is not installed.
std::string headless_chromium(const std::string& profile_dir);

// The value of attribute `name` in a page as `chromium --dump-dom` prints it (with &quot;
// and &amp; decoded), or "" when no element has it.
std::string dom_attribute(const std::string& dom, const std::string& name);

// A fixture with a fresh scratch directory per test (named after the process and the
// test), removed afterwards.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Writes `text` to the scratch file `name`, byte for byte; its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  std::filesystem::path dir_;
};

// Every row of a field table (kStateFields, kSensorFields: name, shape, unit, axes,
// meaning) stands in the document `doc` (a path below the source tree) as the Markdown row
// "| `name` | shape | unit | axes | meaning |".
template <class Table>
void expect_doc_lists_every_field(const std::string& doc, const Table& table) {
  std::ifstream in(std::string(PLASTIVOX_SOURCE_DIR) + "/" + doc);
  std::stringstream text;
  text << in.rdbuf();
  const std::string content = text.str();
  for (const auto& f : table) {
    const std::string row = std::string("| `") + f.name + "` | " + f.shape + " | " + f.unit +
                            " | " + f.axes + " | " + f.meaning + " |";
    EXPECT_NE(content.find(row), std::string::npos) << doc << " lacks the row " << row;
  }
}

}  // namespace plastivox::testing
