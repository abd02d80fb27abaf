// MPI (built when OpenMPI is found): `mpirun -np 2 plastivox evolve` on this machine over
// loopback gives the same content digest as one process, resumes across modes, and
// refuses a different config with rank 0's one-line error.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace plastivox::evo {
namespace {

namespace fs = std::filesystem;

using plastivox::testing::Output;

std::string read_file(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

Output shell(const std::string& cmd) {
  return plastivox::testing::shell(cmd + " 2>&1");
}

// OpenMPI refuses to run as root unless told; LeakSanitizer (sanitizer job) reports
// OpenMPI's own allocations at exit, which are not ours.
std::string mpirun(int ranks) {
  return "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "ASAN_OPTIONS=detect_leaks=0 " +
         std::string(PLASTIVOX_MPIEXEC) + " -np " + std::to_string(ranks) + " --oversubscribe " +
         PLASTIVOX_CLI;
}

class EvoMpi : public plastivox::testing::ScratchDirTest {
 protected:
  // `controller`: the config's controller field, "" for none (the sine).
  std::string config(const std::string& name, int seed, const std::string& controller = "") const {
    std::ofstream(path(name)) << R"({"format": "plastivox-evolve-config", "version": 1, "seed": )"
                              << seed << R"(, "treatment": "pressure", "population": 6,
        "generations": 3, "lattice": {"nx": 4, "ny": 4, "nz": 4},
        "physics": {"duration": 0.2, "settle_time": 0.1})"
                              << (controller.empty() ? "" : ", \"controller\": " + controller)
                              << "}";
    return path(name);
  }
  void two_ranks_give_the_same_digest(const std::string& cfg) const;
  std::string digest(const std::string& results) const {
    const Output o = shell(std::string(PLASTIVOX_CLI) + " inspect " + results + " --json");
    EXPECT_EQ(o.status, 0) << o.out;
    return nlohmann::json::parse(o.out).at("content_digest").get<std::string>();
  }
  fs::path dir_;
};

TEST_F(EvoMpi, TwoRanksGiveTheSameDigestAsOneProcess) {
  for (const std::string controller : {"", R"({"kind": "distributed", "hidden": 2})"}) {
    SCOPED_TRACE(controller);
    two_ranks_give_the_same_digest(config("c.json", 41, controller));
  }
}

// CMA-ES (docs/evolution.md): the samples travel to the other rank as bodies like AFPO's.
TEST_F(EvoMpi, TwoRanksGiveACmaEsRunTheSameDigestAsOneProcess) {
  std::ofstream(path("body.json")) << R"({"format": "plastivox-robot", "version": 1,
      "lattice": {"nx": 2, "ny": 2, "nz": 2, "voxel_size": 0.01}, "voxels": [
      [0, 0, 0, 5e9, 0, 0], [1, 0, 0, 5e9, 0, 0.25], [0, 1, 0, 5e9, 0, 0.5],
      [1, 1, 0, 5e9, 0, -0.25], [0, 0, 1, 5e9, 0, 0], [1, 0, 1, 5e9, 0, 0.1],
      [0, 1, 1, 5e9, 0, 0.2], [1, 1, 1, 5e9, 0, 0.3]]})";
  std::ofstream(path("cma.json")) << R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 43, "generations": 3, "algorithm": "cma-es", "genome": "materials", "body": ")"
                                  << path("body.json") << R"(", "treatment": "pressure",
      "physics": {"duration": 0.2, "settle_time": 0.1}})";
  two_ranks_give_the_same_digest(path("cma.json"));
}

// MAP-Elites (docs/evolution.md): the children travel as AFPO's, their lives' measures come back.
TEST_F(EvoMpi, TwoRanksGiveAMapElitesRunTheSameDigestAsOneProcess) {
  std::ofstream(path("me.json")) << R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 44, "generations": 3, "population": 6, "treatment": "pressure",
      "lattice": {"nx": 4, "ny": 4, "nz": 4}, "algorithm": "map-elites",
      "map_elites": {"descriptors": [{"name": "fill", "bounds": [0.2, 1], "bins": 4},
        {"name": "floor_contact", "bounds": [0, 1], "bins": 4},
        {"name": "development", "bounds": [0, 1], "bins": 2}]},
      "physics": {"duration": 0.2, "settle_time": 0.1}})";
  two_ranks_give_the_same_digest(path("me.json"));
}

// A run's digest is the same on two ranks as in one process (the controller's weights travel
// with each body to the other rank).
void EvoMpi::two_ranks_give_the_same_digest(const std::string& cfg) const {
  fs::remove(path("one.h5"));  // a previous config's
  fs::remove(path("two.h5"));
  const Output one =
      shell(std::string(PLASTIVOX_CLI) + " evolve --config " + cfg + " --out " + path("one.h5"));
  ASSERT_EQ(one.status, 0) << one.out;
  const Output two =
      shell(mpirun(2) + " evolve --config " + cfg + " --out " + path("two.h5") + " --threads 1");
  ASSERT_EQ(two.status, 0) << two.out;
  EXPECT_EQ(digest(path("one.h5")), digest(path("two.h5")));
  // Rank 0 alone reports: one final line, one log line per generation.
  EXPECT_EQ(std::count(two.out.begin(), two.out.end(), '\n'), 5) << two.out;
}

TEST_F(EvoMpi, ResumesAcrossModesAndRefusesAnotherConfig) {
  const std::string cfg = config("c.json", 42);
  ASSERT_EQ(
      shell(std::string(PLASTIVOX_CLI) + " evolve --config " + cfg + " --out " + path("full.h5"))
          .status,
      0);
  // Stopped under MPI after generation 1, finished by a single process.
  const Output part = shell(mpirun(2) + " evolve --config " + cfg + " --out " + path("r.h5") +
                            " --threads 1 --stop-after 1");
  ASSERT_EQ(part.status, 0) << part.out;
  const Output rest =
      shell(std::string(PLASTIVOX_CLI) + " evolve --config " + cfg + " --out " + path("r.h5"));
  ASSERT_EQ(rest.status, 0) << rest.out;
  EXPECT_EQ(digest(path("r.h5")), digest(path("full.h5")));
  // A different config under MPI: rank 0's one error line, non-zero exit, file untouched.
  const Output other = shell(mpirun(2) + " evolve --config " + config("d.json", 43) + " --out " +
                             path("r.h5") + " --threads 1");
  EXPECT_NE(other.status, 0);
  const std::string needle = "different configuration (seed: 42 in the file, 43 now)";
  size_t hits = 0;
  for (size_t at = other.out.find(needle); at != std::string::npos;
       at = other.out.find(needle, at + 1))
    ++hits;
  // Exactly once: rank 0 alone reports, and the other ranks wait for it to print before
  // they exit (with 0), so mpiexec never aborts rank 0 before its line is out.
  EXPECT_EQ(hits, 1u) << other.out;
  EXPECT_EQ(digest(path("r.h5")), digest(path("full.h5")));
}

TEST_F(EvoMpi, AnInvalidConfigIsReportedOnceByRankZero) {
  std::ofstream(path("bad.json")) << R"({"format": "plastivox-evolve-config", "version": 1,
      "population": 0})";
  const Output o = shell(mpirun(2) + " evolve --config " + path("bad.json") + " --out " +
                         path("r.h5") + " --threads 1");
  EXPECT_NE(o.status, 0);
  const std::string needle = "population: must be in [1, 100000], got 0";
  EXPECT_NE(o.out.find(needle), std::string::npos) << o.out;
  EXPECT_EQ(o.out.find(needle), o.out.rfind(needle)) << o.out;
  EXPECT_FALSE(fs::exists(path("r.h5")));
}

// The robustness battery's lives shared by two ranks (apps/battery_ranks.cpp): plastivox
// robustness writes the bytes one process writes, and analyze's stats.json holds the same
// numbers (its provenance aside); rank 0 alone writes checkpoints and outputs.
TEST_F(EvoMpi, TheBatteryOnTwoRanksGivesOneProcesssProfiles) {
  const std::string cli = PLASTIVOX_CLI;
  std::string runs;
  for (int seed : {51, 52}) {
    const std::string out = path("p" + std::to_string(seed) + ".h5");
    ASSERT_EQ(shell(cli + " evolve --config " + config("c.json", seed) + " --out " + out).status,
              0);
    runs += " " + out;
  }
  const std::string args = " robustness" + runs + " --battery small --resamples 200 --threads 1";
  const Output one = shell(cli + args + " --out " + path("one"));
  ASSERT_EQ(one.status, 0) << one.out;
  const Output two = shell(mpirun(2) + args + " --out " + path("two"));
  ASSERT_EQ(two.status, 0) << two.out;
  EXPECT_EQ(read_file(path("one/robustness.json")), read_file(path("two/robustness.json")));
  // Rank 0 alone talks: each of the summary's lines once (not the line count, which the
  // progress lines' timing makes vary, e.g. under the sanitizers).
  const auto once = [&](const std::string& line) {
    EXPECT_NE(two.out.find(line), std::string::npos) << line << "\n" << two.out;
    EXPECT_EQ(two.out.find(line), two.out.rfind(line)) << line << "\n" << two.out;
  };
  once("plastivox robustness: audit: 2 champions re-simulated");
  once("pressure-s51: 14 lives, 0 unstable, 0 sank");
  once("pressure-s52: 14 lives, 0 unstable, 0 sank");
  once("\nwrote ");

  const std::string study = " analyze" + runs + " --battery small --resamples 200 --no-viewer";
  ASSERT_EQ(shell(cli + study + " --out " + path("a1")).status, 0);
  const Output a2 = shell(mpirun(2) + study + " --threads 1 --out " + path("a2"));
  ASSERT_EQ(a2.status, 0) << a2.out;
  nlohmann::json s1 = nlohmann::json::parse(read_file(path("a1/stats.json")));
  nlohmann::json s2 = nlohmann::json::parse(read_file(path("a2/stats.json")));
  s1.erase("provenance");
  s2.erase("provenance");
  EXPECT_EQ(s1, s2);
}

}  // namespace
}  // namespace plastivox::evo
