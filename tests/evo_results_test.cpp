// Results files: round trip, digests, checkpoint/resume equality, refusals, and clear
// errors for truncated, corrupt and foreign files.
#include <hdf5.h>

#include <filesystem>
#include <fstream>

#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/file_seal.hpp"  // engine/evo/src (internal): to build sealed-but-wrong files
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

namespace fs = std::filesystem;

EvolveConfig tiny(uint64_t seed, int generations = 3) {
  EvolveConfig c = parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
      "treatment": "pressure", "population": 6, "lattice": {"nx": 4, "ny": 4, "nz": 4},
      "physics": {"duration": 0.2, "settle_time": 0.1}})",
                                "tiny");
  c.seed = seed;
  c.generations = generations;
  return c;
}

// A fresh scratch directory per test.
class EvoResults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("plastivox_evo_results_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

using plastivox::testing::error_of;

void expect_one_line_error(const std::string& msg, const std::string& needle) {
  EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
}

TEST_F(EvoResults, RoundTripKeepsEverything) {
  const RunReport r = run_evolution(tiny(1), path("r.h5"), {});
  ASSERT_EQ(r.outcome, RunOutcome::kFinished);
  const ResultsFile f = read_results(path("r.h5"));
  const RunState& s = f.state;
  EXPECT_EQ(f.content_digest, r.content_digest);
  EXPECT_EQ(content_digest(s).hex(), r.content_digest);
  EXPECT_EQ(s.generations_done, 3);
  EXPECT_EQ(s.history.size(), 4u);
  EXPECT_EQ(s.births.size(), 6u + 3 * 7);
  EXPECT_EQ(s.population.size(), 6u);
  ASSERT_FALSE(s.champions.empty());
  EXPECT_EQ(s.champions.back().id, s.history.back().champion_id);
  EXPECT_EQ(s.champions.back().phenotype.nx, 4);
  EXPECT_EQ(f.provenance.plastivox_version.empty(), false);
  EXPECT_FALSE(f.provenance.date_created.empty());
  // The flags themselves, the CMake generator expressions they come from evaluated.
  EXPECT_NE(f.provenance.compiler_flags.find("-ffp-contract=off"), std::string::npos)
      << f.provenance.compiler_flags;
  EXPECT_NE(f.provenance.compiler_flags.find("-UNDEBUG"), std::string::npos)
      << f.provenance.compiler_flags;
  EXPECT_EQ(f.provenance.compiler_flags.find("$<"), std::string::npos)
      << f.provenance.compiler_flags;
  EXPECT_FALSE(fs::exists(path("r.h5.tmp")));  // the temporary file was renamed
}

TEST_F(EvoResults, StopAndResumeEqualsUninterrupted) {
  const RunReport full = run_evolution(tiny(2), path("full.h5"), {});
  RunOptions stop;
  stop.stop_after = 1;
  stop.threads = 1;
  EXPECT_EQ(run_evolution(tiny(2), path("part.h5"), stop).outcome, RunOutcome::kStopped);
  EXPECT_EQ(read_results(path("part.h5")).state.generations_done, 1);
  stop.stop_after = 2;
  stop.threads = 2;
  const RunReport mid = run_evolution(tiny(2), path("part.h5"), stop);
  EXPECT_EQ(mid.resumed_from, 1);
  EXPECT_EQ(mid.generations_done, 2);
  const RunReport rest = run_evolution(tiny(2), path("part.h5"), {});
  EXPECT_EQ(rest.outcome, RunOutcome::kFinished);
  EXPECT_EQ(rest.resumed_from, 2);
  EXPECT_EQ(rest.content_digest, full.content_digest);
  EXPECT_EQ(read_results(path("part.h5")).content_digest, full.content_digest);
}

TEST_F(EvoResults, CheckpointEveryKStillResumesExactly) {
  EvolveConfig c = tiny(3);
  const RunReport full = run_evolution(c, path("full.h5"), {});
  c.checkpoint_every = 3;  // run control: allowed to differ between sessions
  RunOptions stop;
  stop.stop_after = 2;
  run_evolution(c, path("k.h5"), stop);
  const RunReport rest = run_evolution(c, path("k.h5"), {});
  EXPECT_EQ(rest.content_digest, full.content_digest);
}

TEST_F(EvoResults, FinishedRunIsLeftUntouched) {
  run_evolution(tiny(4, 2), path("r.h5"), {});
  const auto before = fs::last_write_time(path("r.h5"));
  std::ifstream in(path("r.h5"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const RunReport again = run_evolution(tiny(4, 2), path("r.h5"), {});
  EXPECT_EQ(again.outcome, RunOutcome::kAlreadyFinished);
  std::ifstream in2(path("r.h5"), std::ios::binary);
  EXPECT_EQ(bytes, std::string((std::istreambuf_iterator<char>(in2)), {}));
  EXPECT_EQ(before, fs::last_write_time(path("r.h5")));
}

TEST_F(EvoResults, DifferentConfigRefusesToResume) {
  RunOptions stop;
  stop.stop_after = 0;
  run_evolution(tiny(5), path("r.h5"), stop);
  const std::string msg = error_of([&] { run_evolution(tiny(6), path("r.h5"), {}); });
  expect_one_line_error(msg, "different configuration (seed: 5 in the file, 6 now)");
  EvolveConfig other_physics = tiny(5);
  other_physics.physics_json = R"({"duration":0.3,"settle_time":0.1})";
  other_physics.physics.duration = 0.3;
  expect_one_line_error(error_of([&] { run_evolution(other_physics, path("r.h5"), {}); }),
                        "physics.duration");
  // Nothing was lost: the file still holds generation 0 of seed 5.
  EXPECT_EQ(read_results(path("r.h5")).state.config.seed, 5u);
}

TEST_F(EvoResults, ASecondRunOnTheSameFileIsRefused) {
  RunOptions opt;
  opt.stop_after = 0;
  std::string inner;
  opt.on_generation = [&](const RunProgress&) {
    inner = error_of([&] { run_evolution(tiny(8), path("r.h5"), {}); });
  };
  run_evolution(tiny(8), path("r.h5"), opt);
  expect_one_line_error(inner, "another plastivox evolve is running on this file");
  // Once the first has ended the lock is free again.
  EXPECT_EQ(run_evolution(tiny(8), path("r.h5"), {}).outcome, RunOutcome::kFinished);
}

TEST_F(EvoResults, TruncatedAndCorruptFilesGiveOneLineErrors) {
  run_evolution(tiny(7, 1), path("r.h5"), {});
  std::ifstream in(path("r.h5"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  auto write = [&](const std::string& name, const std::string& data) {
    std::ofstream(path(name), std::ios::binary) << data;
    return path(name);
  };
  for (size_t len : {size_t{0}, size_t{10}, size_t{511}, size_t{512}, size_t{2000},
                     bytes.size() / 2, bytes.size() - 1}) {
    const std::string p = write("t.h5", bytes.substr(0, len));
    const std::string msg = error_of([&] { read_results(p); });
    EXPECT_EQ(msg.find("(no error)"), std::string::npos) << len;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  expect_one_line_error(error_of([&] { read_results(write("t.h5", bytes.substr(0, 4000))); }),
                        "truncated");
  for (size_t at : {size_t{600}, bytes.size() / 3, bytes.size() - 100}) {
    std::string bad = bytes;
    bad[at] = static_cast<char>(bad[at] ^ 0x5a);
    expect_one_line_error(error_of([&] { read_results(write("c.h5", bad)); }), "corrupt");
    // A file changed in place says how to get the data out instead.
    expect_one_line_error(error_of([&] { read_results(write("c.h5", bad)); }),
                          "read it with h5py.File(path, 'r') and copy what you need");
  }
  expect_one_line_error(error_of([&] { read_results(write("grown.h5", bytes + "appended")); }),
                        "copy what you need into a new file");
  expect_one_line_error(error_of([&] { read_results(write("x.h5", "not hdf5 at all\n")); }),
                        "not a plastivox evolution results file");
  expect_one_line_error(error_of([&] { read_results(path("missing.h5")); }), "no such file");
  // The same errors stop evolve from touching such a file.
  const std::string junk = write("junk.h5", "precious data");
  expect_one_line_error(error_of([&] { run_evolution(tiny(7, 1), junk, {}); }),
                        "not a plastivox evolution results file");
  std::ifstream j(junk);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(j)), {}), "precious data");
}

// An HDF5 file written by someone else.
void write_foreign_hdf5(const std::string& p, bool with_userblock) {
  const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (with_userblock) H5Pset_userblock(fcpl, 512);
  const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hsize_t n = 3;
  const hid_t sp = H5Screate_simple(1, &n, nullptr);
  const hid_t d = H5Dcreate2(f, "data", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double v[3] = {1, 2, 3};
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
  if (with_userblock) {  // pretend to be ours at the root: right format attribute only
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, 20);
    const hid_t s1 = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, "format", t, s1, H5P_DEFAULT, H5P_DEFAULT);
    const char text[20] = "plastivox-evolution";
    H5Awrite(a, t, text);
    H5Aclose(a);
    H5Sclose(s1);
    H5Tclose(t);
  }
  H5Dclose(d);
  H5Sclose(sp);
  H5Fclose(f);
  H5Pclose(fcpl);
}

TEST_F(EvoResults, ForeignHdf5FilesAreRefused) {
  write_foreign_hdf5(path("foreign.h5"), false);
  expect_one_line_error(error_of([&] { read_results(path("foreign.h5")); }),
                        "an HDF5 file, but not a plastivox evolution results file");
  // Sealed and carrying our format name, but without the rest: every check still holds.
  write_foreign_hdf5(path("fake.h5"), true);
  seal::write_seal(path("fake.h5"), "fake.h5");
  expect_one_line_error(error_of([&] { read_results(path("fake.h5")); }), "format_version");
}

}  // namespace
}  // namespace plastivox::evo
