// plastivox export through the binary: a champion written as VXA re-simulates to exactly
// the fitness the evolution recorded; bad inputs give one-line errors.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

using CliRun = testing::Output;

class ExportTest : public testing::ScratchDirTest {
 protected:
  void SetUp() override {
    testing::ScratchDirTest::SetUp();
    // A tiny run: 5x5x5 lattice, population 4, 2 generations, 0.3 s lives.
    const CliRun cfg = cli("evolve --print-default-config");
    ASSERT_EQ(cfg.status, 0) << cfg.out;
    nlohmann::json c = nlohmann::json::parse(cfg.out);
    c["generations"] = 2;
    c["population"] = 4;
    c["treatment"] = "pressure";
    c["lattice"] = {{"nx", 5}, {"ny", 5}, {"nz", 5}, {"voxel_size", 0.01}};
    c["physics"] = {{"preset", "gecco2018-code"}, {"duration", 0.3}, {"settle_time", 0.1}};
    std::ofstream(dir_ / "tiny.json") << c.dump();
    const CliRun evo = cli("evolve --config " + (dir_ / "tiny.json").string() + " --out " +
                           (dir_ / "tiny.h5").string() + " --threads 1");
    ASSERT_EQ(evo.status, 0) << evo.out;
  }
};

double json_number(const std::string& text, const char* key) {
  return nlohmann::json::parse(text).at(key).get<double>();
}

TEST_F(ExportTest, ChampionAsVxaResimulatesToTheRecordedFitness) {
  const CliRun info = cli("inspect " + (dir_ / "tiny.h5").string() + " --json");
  ASSERT_EQ(info.status, 0) << info.out;
  const double best = json_number(info.out, "best_fitness");
  const CliRun ex =
      cli("export " + (dir_ / "tiny.h5").string() + " --out " + (dir_ / "c.vxa").string());
  ASSERT_EQ(ex.status, 0) << ex.out;
  const CliRun sim = cli("simulate " + (dir_ / "c.vxa").string() + " --json");
  ASSERT_EQ(sim.status, 0) << sim.out;
  // The simulate output may be preceded by warning lines on stderr (merged here).
  const std::string json = sim.out.substr(sim.out.find('{'));
  EXPECT_EQ(json_number(json, "fitness"), best);  // bit for bit: same robot, same physics
}

// inspect's champion generation cannot be read as the generation export names the champion by:
// champion_since_generation is when it first became the best, export's is the last done.
TEST_F(ExportTest, InspectSaysSinceWhenTheExportedChampionLeads) {
  const CliRun info = cli("inspect " + (dir_ / "tiny.h5").string() + " --json");
  ASSERT_EQ(info.status, 0) << info.out;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  EXPECT_FALSE(j.contains("champion_generation")) << info.out;
  const int since = j.at("champion_since_generation").get<int>();
  const int done = j.at("generations_done").get<int>();
  EXPECT_LE(since, done);
  const CliRun text = cli("inspect " + (dir_ / "tiny.h5").string());
  EXPECT_NE(text.out.find("since generation " + std::to_string(since) + ")"), std::string::npos)
      << text.out;
  const CliRun ex =
      cli("export " + (dir_ / "tiny.h5").string() + " --out " + (dir_ / "c.json").string());
  ASSERT_EQ(ex.status, 0) << ex.out;
  EXPECT_NE(ex.out.find("champion " + std::to_string(j.at("champion_id").get<uint64_t>())),
            std::string::npos)
      << ex.out;
  EXPECT_NE(ex.out.find("at generation " + std::to_string(done)), std::string::npos) << ex.out;
  // Every key is documented.
  std::ifstream in(std::string(PLASTIVOX_SOURCE_DIR) + "/docs/results-format.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), {});
  for (const auto& [key, value] : j.items())
    if (doc.find("`" + key + "`") == std::string::npos)
      ADD_FAILURE() << "docs/results-format.md does not name inspect's key " << key;
}

TEST_F(ExportTest, ChampionAsPlastivoxRobotFile) {
  const CliRun ex = cli("export " + (dir_ / "tiny.h5").string() + " --out " +
                        (dir_ / "c.json").string() + " --generation 1");
  ASSERT_EQ(ex.status, 0) << ex.out;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "c.json"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "c.json.tmp"));
}

TEST_F(ExportTest, BadInputGivesOneLineErrors) {
  const CliRun not_h5 =
      cli("export " + (dir_ / "tiny.json").string() + " --out " + (dir_ / "x.vxa").string());
  EXPECT_NE(not_h5.status, 0);
  EXPECT_NE(not_h5.out.find("tiny.json"), std::string::npos) << not_h5.out;
  const CliRun bad_ext =
      cli("export " + (dir_ / "tiny.h5").string() + " --out " + (dir_ / "x.txt").string());
  EXPECT_NE(bad_ext.status, 0);
  const CliRun bad_gen = cli("export " + (dir_ / "tiny.h5").string() + " --out " +
                             (dir_ / "x.vxa").string() + " --generation 99");
  EXPECT_NE(bad_gen.status, 0);
  EXPECT_NE(bad_gen.out.find("beyond"), std::string::npos) << bad_gen.out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.vxa"));
}

// --format voxcraft: refused in one line while the robot develops, written under --lossy,
// and the pair simulates with --vxd.
TEST_F(ExportTest, VoxcraftFilesForARobotFileSimulateWithVxd) {
  const std::string walker = std::string(PLASTIVOX_SOURCE_DIR) + "/examples/walker.json";
  const std::filesystem::path out = dir_ / "walker_voxcraft";
  const CliRun refused = cli("export " + walker + " --format voxcraft --out " + out.string());
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.out.find("plastivox export: error: voxcraft export: development"),
            std::string::npos)
      << refused.out;
  EXPECT_FALSE(std::filesystem::exists(out / "base.vxa"));
  const CliRun lossy = cli("export " + walker + " --format voxcraft --lossy --out " + out.string());
  ASSERT_EQ(lossy.status, 0) << lossy.out;
  EXPECT_NE(lossy.out.find("warning: development"), std::string::npos) << lossy.out;
  EXPECT_NE(lossy.out.find("largest stiffness error"), std::string::npos) << lossy.out;
  const CliRun sim = cli("simulate " + (out / "base.vxa").string() + " --vxd " +
                         (out / "robot.vxd").string() + " --json");
  ASSERT_EQ(sim.status, 0) << sim.out;
  const std::string json = sim.out.substr(sim.out.find('{'));
  EXPECT_GT(json_number(json, "fitness"), 0.5);
  EXPECT_EQ(json_number(json, "voxels"), 512);
  // Bad command lines and files: one line each.
  EXPECT_EQ(cli("simulate " + (out / "robot.vxd").string() + " --vxd x.vxd").status, 2);
  const CliRun missing =
      cli("simulate " + (out / "base.vxa").string() + " --vxd " + (dir_ / "none.vxd").string());
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.out.find("none.vxd"), std::string::npos) << missing.out;
  EXPECT_EQ(cli("export " + walker + " --lossy --out " + (dir_ / "w.json").string()).status, 2);
  // A run's champion, as for .vxa.
  const std::filesystem::path champ = dir_ / "champion_voxcraft";
  const CliRun run_export = cli("export " + (dir_ / "tiny.h5").string() +
                                " --format voxcraft --lossy --out " + champ.string());
  ASSERT_EQ(run_export.status, 0) << run_export.out;
  EXPECT_NE(run_export.out.find("champion"), std::string::npos) << run_export.out;
  EXPECT_EQ(
      cli("simulate " + (champ / "base.vxa").string() + " --vxd " + (champ / "robot.vxd").string())
          .status,
      0);
}

// A robot file whose physics differs from what VXA import reads back in a field the authors'
// dialect has no tag for (here the sinking rule) exports with a warning naming the field: a
// life that sank is judged differently once exported. The file as it is exports without one.
class ExportRules : public testing::ScratchDirTest {};

TEST_F(ExportRules, VxaExportWarnsForARuleItDrops) {
  const std::string walker = std::string(PLASTIVOX_SOURCE_DIR) + "/examples/walker.json";
  const CliRun plain = cli("export " + walker + " --out " + path("plain.vxa"));
  ASSERT_EQ(plain.status, 0) << plain.out;
  EXPECT_EQ(plain.out.find("warning"), std::string::npos) << plain.out;
  nlohmann::json robot = nlohmann::json::parse(testing::file_text(walker));
  robot["physics"]["sinking_invalid"] = false;
  robot["physics"]["max_speed"] = 50;
  const std::string changed = write("lenient.json", robot.dump());
  const CliRun warned = cli("export " + changed + " --out " + path("lenient.vxa"));
  ASSERT_EQ(warned.status, 0) << warned.out;
  EXPECT_NE(warned.out.find("plastivox export: warning: write_vxa: physics.sinking_invalid false "
                            "is not carried; VXA import uses true"),
            std::string::npos)
      << warned.out;
  EXPECT_NE(warned.out.find("plastivox export: warning: write_vxa: physics.max_speed 50 is not "
                            "carried; VXA import uses 100 m/s"),
            std::string::npos)
      << warned.out;
  EXPECT_TRUE(std::filesystem::exists(path("lenient.vxa")));
}

}  // namespace
}  // namespace plastivox
