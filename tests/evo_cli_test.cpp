// The command-line contract of `plastivox evolve` and `plastivox inspect`, through the
// real binary: default config, config errors, determinism across --threads, a real
// kill -9 and resume, and refusal of damaged files.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "plastivox/evo/config.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

using plastivox::testing::cli;

namespace fs = std::filesystem;

using plastivox::testing::Output;

std::string read_file(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

class EvoCli : public plastivox::testing::ScratchDirTest {
 protected:
  // A tiny run: 4x4x4 lattice, population 6, 0.2 s lives; `controller` the config's
  // controller field ("" for none: the sine).
  std::string tiny_config(const std::string& name, int seed, int generations,
                          const std::string& controller = "") const {
    return write(name, R"({"format": "plastivox-evolve-config", "version": 1, "seed": )" +
                           std::to_string(seed) + R"(, "treatment": "stress", "population": 6,
        "generations": )" + std::to_string(generations) +
                           R"(, "lattice": {"nx": 4, "ny": 4, "nz": 4},
        "physics": {"duration": 0.2, "settle_time": 0.1})" +
                           (controller.empty() ? "" : ", \"controller\": " + controller) + "}");
  }
  void kill_nine_and_resume(const std::string& cfg) const;
  // full.h5's champion, exported, simulates to its fitness bit for bit (`inspected`: inspect's
  // JSON of the file).
  void exported_champion_replays(const nlohmann::json& inspected) const {
    ASSERT_EQ(cli("export " + path("full.h5") + " --out " + path("champ.json")).status, 0);
    const Output s = cli("simulate " + path("champ.json") + " --json");
    ASSERT_EQ(s.status, 0) << s.out;
    EXPECT_EQ(nlohmann::json::parse(s.out)["fitness"].get<double>(),
              inspected["best_fitness"].get<double>());
  }
  std::string digest(const std::string& results) const {
    const Output o = cli("inspect " + results + " --json");
    EXPECT_EQ(o.status, 0) << o.out;
    return nlohmann::json::parse(o.out).at("content_digest").get<std::string>();
  }
  fs::path dir_;
};

TEST_F(EvoCli, DefaultConfigIsCompleteAndParsesBack) {
  const Output o = cli("evolve --print-default-config");
  ASSERT_EQ(o.status, 0) << o.out;
  const EvolveConfig c = parse_config(o.out, "default");
  EXPECT_EQ(c.population, 24);
  EXPECT_EQ(c.generations, 5000);
  EXPECT_EQ(c.nx * c.ny * c.nz, 1000);
  EXPECT_EQ(c.max_mutation_tries, 1500);
  EXPECT_EQ(c.geometry, GeometryRule::kLargestComponent);
  const auto j = nlohmann::json::parse(o.out);
  for (const char* k : {"_comment", "seed", "treatment", "population", "generations", "lattice",
                        "geometry", "min_fill", "max_mutation_tries", "checkpoint_every", "threads",
                        "physics", "format", "version"})
    EXPECT_TRUE(j.contains(k)) << k;
}

TEST_F(EvoCli, InvalidConfigsNameTheField) {
  const std::string head = R"({"format": "plastivox-evolve-config", "version": 1, )";
  const struct {
    std::string body, expect;
  } cases[] = {
      {"{nope", "not valid JSON"},
      {R"({"version": 1})", "format"},
      {R"({"format": "plastivox-evolve-config", "version": 2})", "version: unsupported version 2"},
      {head + R"("population": 0})", "population: must be in [1, 100000], got 0"},
      {head + R"("population": "six"})", "population: expected an integer"},
      {head + R"("popsize": 6})", "popsize: unknown field"},
      {head + R"("treatment": "growth"})", "treatment: treatment 'growth' is unknown"},
      {head + R"("lattice": {"nx": 0}})", "lattice.nx: must be in [1, 100]"},
      {head + R"("lattice": {"nw": 3}})", "lattice.nw: unknown field"},
      {head + R"("geometry": "blob"})", "geometry: geometry rule 'blob' is unknown"},
      {head + R"("seed": -1})", "seed: expected a non-negative integer"},
      {head + R"("min_fill": 1.5})", "min_fill: must be in [0, 1]"},
      {head + R"("threads": -1})", "threads: must be in [0, 4096]"},
      {head + R"("checkpoint_every": 0})", "checkpoint_every: must be in"},
      {head + R"("physics": {"duration": -1}})", "physics.duration"},
      {head + R"("physics": {"bogus": 1}})", "physics.bogus: unknown field"},
      {head + R"("physics": {"treatment": "none"}})", "physics.treatment: set the treatment"},
      {head + R"("physics": {"preset": "gecco1999"}})", "physics.preset"},
      {head + R"("controller": {"kind": "neural"}})", "controller.kind: 'neural' is not a"},
      {head + R"("controller": {"kind": "distributed", "hidden": -1}})",
       "controller.hidden: must be in [0, 64]"},
      {head + R"("controller": {"kind": "distributed", "mutation_sigma": "big"}})",
       "controller.mutation_sigma: expected a number"},
  };
  for (const auto& c : cases) {
    const std::string cfg = write("bad.json", c.body);
    const Output o = cli("evolve --config " + cfg + " --out " + path("r.h5"));
    EXPECT_EQ(o.status, 1) << c.body << "\n" << o.out;
    EXPECT_NE(o.out.find(c.expect), std::string::npos) << c.body << "\n" << o.out;
    EXPECT_NE(o.out.find("bad.json"), std::string::npos) << o.out;        // names the file
    EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;  // one line
    EXPECT_FALSE(fs::exists(path("r.h5")));
  }
  EXPECT_EQ(cli("evolve --config " + path("absent.json") + " --out " + path("r.h5")).status, 1);
  EXPECT_EQ(cli("evolve --out " + path("r.h5")).status, 2);  // usage
  EXPECT_EQ(cli("evolve --config x.json").status, 2);
  EXPECT_EQ(cli("evolve --config x.json --out y.h5 --threads two").status, 2);
  EXPECT_EQ(cli("inspect").status, 2);
}

TEST_F(EvoCli, SameSeedSameDigestWithOneAndTwoThreads) {
  const std::string cfg = tiny_config("c.json", 21, 3);
  const Output a = cli("evolve --config " + cfg + " --out " + path("a.h5") + " --threads 1");
  const Output b = cli("evolve --config " + cfg + " --out " + path("b.h5") + " --threads 2");
  ASSERT_EQ(a.status, 0) << a.out;
  ASSERT_EQ(b.status, 0) << b.out;
  EXPECT_EQ(digest(path("a.h5")), digest(path("b.h5")));
  const auto j = nlohmann::json::parse(cli("inspect " + path("b.h5") + " --json").out);
  EXPECT_EQ(j["treatment"], "stress");
  EXPECT_EQ(j["seed"], 21);
  EXPECT_EQ(j["generations_done"], 3);
  EXPECT_EQ(j["finished"], true);
  EXPECT_TRUE(j.contains("best_fitness"));
  EXPECT_TRUE(j.contains("champion_id"));
  EXPECT_EQ(j["threads"], 2);
  // Every provenance field, under its attribute name in the file.
  for (const char* k : {"plastivox_version", "git_commit", "compiler", "compiler_flags",
                        "build_type", "date_created", "date_updated", "host", "wall_seconds"})
    EXPECT_TRUE(j.contains(k)) << k;
  // Counts read as English: "on 1 thread", "on 2 threads".
  EXPECT_NE(a.out.find("finished 3 generations on 1 thread;"), std::string::npos) << a.out;
  EXPECT_NE(b.out.find("finished 3 generations on 2 threads;"), std::string::npos) << b.out;
  // Not a terminal: plain log lines, one per generation (0..3).
  EXPECT_NE(a.out.find("generation 3/3"), std::string::npos) << a.out;
  EXPECT_EQ(a.out.find('\r'), std::string::npos);
}

// Runs the config to its end, then again killed with SIGKILL soon after its first checkpoint
// and resumed: the same digest.
void EvoCli::kill_nine_and_resume(const std::string& cfg) const {
  ASSERT_EQ(cli("evolve --config " + cfg + " --out " + path("full.h5")).status, 0);
  const std::string full = digest(path("full.h5"));

  // Start the same run and kill -9 it soon after its first checkpoint appears.
  const std::string out = path("killed.h5");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    ::execl(PLASTIVOX_CLI, PLASTIVOX_CLI, "evolve", "--config", cfg.c_str(), "--out", out.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  ::kill(pid, SIGKILL);
  int st = 0;
  ::waitpid(pid, &st, 0);
  const bool killed = WIFSIGNALED(st);
  if (!killed) std::fprintf(stderr, "note: the run finished before it could be killed\n");
  // Whatever moment it died at, the file is a complete checkpoint.
  const Output mid = cli("inspect " + out + " --json");
  ASSERT_EQ(mid.status, 0) << mid.out;
  if (killed) {
    EXPECT_EQ(nlohmann::json::parse(mid.out)["finished"], false);
  }

  const Output resumed = cli("evolve --config " + cfg + " --out " + out);
  ASSERT_EQ(resumed.status, 0) << resumed.out;
  if (killed) {
    EXPECT_NE(resumed.out.find("resuming after generation"), std::string::npos) << resumed.out;
  }
  EXPECT_EQ(digest(out), full);

  // A finished run says so and changes nothing.
  const std::string bytes = read_file(out);
  const Output again = cli("evolve --config " + cfg + " --out " + out);
  EXPECT_EQ(again.status, 0);
  EXPECT_NE(again.out.find("already finished"), std::string::npos) << again.out;
  EXPECT_EQ(read_file(out), bytes);
}

TEST_F(EvoCli, KillNineAndResumeEqualsUninterrupted) {
  kill_nine_and_resume(tiny_config("c.json", 33, 8));
}

// The controller's weights are part of the checkpoint: a killed run resumes to the same bits.
TEST_F(EvoCli, KillNineAndResumeWithADistributedControllerEqualsUninterrupted) {
  kill_nine_and_resume(
      tiny_config("c.json", 34, 8, R"({"kind": "distributed", "hidden": 4, "every": 1})"));
}

// A 3x2x2 robot file (5e9 Pa, phases along x) for CMA-ES runs, with a distributed
// controller when `neural`.
std::string block_robot(bool neural) {
  std::string voxels;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x)
        voxels += (voxels.empty() ? "[" : ", [") + std::to_string(x) + ", " + std::to_string(y) +
                  ", " + std::to_string(z) + ", 5e9, 0.5, " + std::to_string(0.25 * x) + "]";
  return R"({"format": "plastivox-robot", "version": 1, "name": "block",
      "lattice": {"nx": 3, "ny": 2, "nz": 2, "voxel_size": 0.01}, "voxels": [)" +
         voxels + "]" +
         (neural ? R"(, "controller": {"kind": "distributed", "hidden": 2, "every": 1}})" : "}");
}

// A CMA-ES run (docs/evolution.md, "CMA-ES"): killed and resumed, the same bits; inspect says
// what it searched; its exported champion is the body with the genome and replays its
// fitness; the study refuses it in one line.
TEST_F(EvoCli, ACmaEsRunResumesAfterKillNineExportsItsChampionAndTheStudyReadsIt) {
  const std::string body = write("block.json", block_robot(false));
  const std::string cfg = write("cma.json", R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 8, "generations": 8, "algorithm": "cma-es", "genome": "phase", "body": ")" +
                                                body + R"(", "treatment": "stress",
      "physics": {"duration": 0.4, "settle_time": 0.2}})");
  kill_nine_and_resume(cfg);
  const Output i = cli("inspect " + path("full.h5") + " --json");
  ASSERT_EQ(i.status, 0) << i.out;
  const auto j = nlohmann::json::parse(i.out);
  EXPECT_EQ(j["algorithm"], "cma-es");
  EXPECT_EQ(j["genome"], "phase");
  EXPECT_EQ(j["genome_dimension"], 12);
  EXPECT_EQ(j["covariance"], "full");
  exported_champion_replays(j);
  // The study reads any results file the evolver writes: the champion audited, its fitness
  // the recorded one.
  const Output a = cli("analyze " + path("full.h5") + " --out " + path("study") + " --no-viewer");
  ASSERT_EQ(a.status, 0) << a.out;
  const auto stats = nlohmann::json::parse(read_file(path("study/stats.json")));
  EXPECT_EQ(stats["champions"][0]["fitness"].get<double>(), j["best_fitness"].get<double>());
}

// A MAP-Elites run (docs/evolution.md, "MAP-Elites"): killed and resumed, the same bits;
// inspect gives the archive's coverage and QD score; the exported champion (the best elite)
// replays its fitness; the study reads it.
TEST_F(EvoCli, AMapElitesRunResumesAfterKillNineExportsItsChampionAndTheStudyReadsIt) {
  const std::string cfg = write("me.json", R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 9, "generations": 8, "population": 6, "treatment": "stress",
      "lattice": {"nx": 4, "ny": 4, "nz": 4}, "algorithm": "map-elites",
      "map_elites": {"descriptors": [{"name": "voxels", "bounds": [12, 64], "bins": 6},
        {"name": "com_height", "bounds": [0, 3], "bins": 6}]},
      "physics": {"duration": 0.2, "settle_time": 0.1, "fitness": "xy"}})");
  kill_nine_and_resume(cfg);
  const Output i = cli("inspect " + path("full.h5") + " --json");
  ASSERT_EQ(i.status, 0) << i.out;
  const auto j = nlohmann::json::parse(i.out);
  EXPECT_EQ(j["algorithm"], "map-elites");
  EXPECT_EQ(j["cells"], 36);
  EXPECT_GT(j["filled"].get<int>(), 1);
  EXPECT_EQ(j["coverage"].get<double>(), j["filled"].get<double>() / 36);
  EXPECT_GE(j["qd_score"].get<double>(), j["best_fitness"].get<double>());
  EXPECT_NE(cli("inspect " + path("full.h5")).out.find("map-elites archive: "), std::string::npos);
  exported_champion_replays(j);
  // The study reads it: the champion is the best elite, audited; the curve's best is the
  // archive's best at each generation, so it never falls.
  const Output a = cli("analyze " + path("full.h5") + " --out " + path("study") + " --no-viewer");
  ASSERT_EQ(a.status, 0) << a.out;
  const auto stats = nlohmann::json::parse(read_file(path("study/stats.json")));
  EXPECT_EQ(stats["champions"][0]["fitness"].get<double>(), j["best_fitness"].get<double>());
  const auto best = stats["evolution"]["runs"][0]["best_fitness"];
  ASSERT_EQ(best.size(), 9u) << best;
  EXPECT_EQ(best.back().get<double>(), j["best_fitness"].get<double>()) << best;
  for (size_t g = 1; g < best.size(); ++g)
    EXPECT_GE(best[g].get<double>(), best[g - 1].get<double>());
  // plastivox archive: the map (a rect per cell, as many filled as the archive), the table (a
  // row per elite) and the gallery; a run without an archive is refused in one line.
  const Output m = cli("archive " + path("full.h5") + " --out " + path("map") +
                       " --elites 3 --size 640x360 --axes com_height,voxels");
  ASSERT_EQ(m.status, 0) << m.out;
  const std::string svg = read_file(path("map/archive.svg"));
  const auto count = [&](const std::string& what) {
    size_t n = 0;
    for (size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("class=\"cell\""), 36u);
  EXPECT_EQ(36u - count("data-group=\"empty\""), j["filled"].get<size_t>());
  const std::string csv = read_file(path("map/archive.csv"));
  EXPECT_EQ(static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')),
            j["filled"].get<size_t>() + 1);
  EXPECT_EQ(csv.rfind("cell,bin_voxels,bin_com_height,voxels,com_height,fitness,", 0), 0u) << csv;
  EXPECT_GT(read_file(path("map/archive.png")).size(), 1000u);
  EXPECT_GT(read_file(path("map/elites.png")).size(), 1000u);
  ASSERT_EQ(
      cli("evolve --config " + tiny_config("afpo.json", 3, 0) + " --out " + path("afpo.h5")).status,
      0);
  const Output refused = cli("archive " + path("afpo.h5") + " --out " + path("none"));
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.out.find(path("afpo.h5") + ": algorithm afpo keeps no archive"),
            std::string::npos)
      << refused.out;
}

TEST_F(EvoCli, DamagedAndForeignFilesGiveOneLineErrors) {
  const std::string cfg = tiny_config("c.json", 5, 1);
  ASSERT_EQ(cli("evolve --config " + cfg + " --out " + path("r.h5")).status, 0);
  const std::string bytes = read_file(path("r.h5"));
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 1);
  const struct {
    std::string name, data, expect;
  } cases[] = {
      {"truncated.h5", bytes.substr(0, bytes.size() / 2), "truncated"},
      {"corrupt.h5", flipped, "corrupt"},
      {"text.h5", "hello\n", "not a plastivox evolution results file"},
      {"empty.h5", "", "empty file"},
  };
  for (const auto& c : cases) {
    const std::string p = write(c.name, c.data);
    const Output o = cli("inspect " + p + " --json");
    EXPECT_EQ(o.status, 1) << c.name << ": " << o.out;
    EXPECT_NE(o.out.find(c.expect), std::string::npos) << o.out;
    EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
    // evolve refuses to resume into it and leaves it alone.
    const Output e = cli("evolve --config " + cfg + " --out " + p);
    EXPECT_EQ(e.status, 1) << e.out;
    EXPECT_EQ(read_file(p), c.data);
  }
  const Output other =
      cli("evolve --config " + tiny_config("d.json", 6, 1) + " --out " + path("r.h5"));
  EXPECT_EQ(other.status, 1);
  EXPECT_NE(other.out.find("different configuration (seed: 5 in the file, 6 now)"),
            std::string::npos)
      << other.out;
  EXPECT_EQ(cli("inspect " + path("nothing.h5")).status, 1);
}

// docs/evolution.md, "Flagged lives": without a floor every life falls, none counts, and the
// champion is a falling life, which inspect names and never calls a success; on the floor the
// same run's champion is a life that counts.
TEST_F(EvoCli, InspectSaysWhenTheChampionScoredByFalling) {
  const auto inspected = [&](const std::string& name, bool floor) {
    const std::string cfg = write(name + ".json", R"({"format": "plastivox-evolve-config",
        "version": 1, "seed": 2, "treatment": "stress", "population": 4, "generations": 1,
        "lattice": {"nx": 4, "ny": 4, "nz": 4},
        "physics": {"duration": 0.2, "settle_time": 0.1, "floor": )" +
                                                      std::string(floor ? "true" : "false") + "}}");
    const Output e = cli("evolve --config " + cfg + " --out " + path(name + ".h5"));
    EXPECT_EQ(e.status, 0) << e.out;
    const Output o = cli("inspect " + path(name + ".h5"));
    EXPECT_EQ(o.out.find("scored by rising or falling") != std::string::npos, !floor) << o.out;
    return nlohmann::json::parse(cli("inspect " + path(name + ".h5") + " --json").out);
  };
  const nlohmann::json falls = inspected("falls", false);
  EXPECT_EQ(falls.at("champion_status"), "ok");
  EXPECT_EQ(falls.at("champion_vertical"), true);
  EXPECT_EQ(falls.at("champion_success"), false);
  EXPECT_EQ(inspected("stands", true).at("champion_vertical"), false);
}

}  // namespace
}  // namespace plastivox::evo
