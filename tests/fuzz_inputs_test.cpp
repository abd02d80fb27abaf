// Seeded, bounded fuzzing of every reader (issue 14): the VXA reader, the robot JSON reader,
// the evolution and experiment config readers and the results-file reader each get a few
// hundred damaged versions of a valid input. Every one must either parse or be refused with
// the reader's own error type and a one-line message naming the source: no crash, no other
// exception (std::bad_alloc, a JSON library error), no message split over lines. A sample
// also goes through the real binary, which must exit 1 with one error line (or run).
// Deterministic (one pinned engine, fixed seeds) and a few seconds long, so it runs in the
// sanitizer job as well.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "experiment/experiment_config.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/child_read.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/vxa.hpp"
#include "plastivox/model.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

namespace fs = std::filesystem;

std::string read_file(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Damage to text: byte changes to characters that matter to XML, JSON and numbers, deleted,
// repeated and moved spans, truncation, numbers replaced by extreme ones. The engine's raw
// output is used (no std distributions, which differ between standard libraries).
class Mutator {
 public:
  explicit Mutator(uint64_t seed) : rng_(seed) {}
  std::string operator()(std::string s) {
    const int edits = 1 + static_cast<int>(below(4));
    for (int e = 0; e < edits && !s.empty(); ++e) {
      const size_t at = below(s.size());
      switch (below(7)) {
        case 0: {
          static const char kChars[] = "<>/=\"'![]{},:-+.e0123456789\n\r\t \x01\xff";
          s[at] = kChars[below(sizeof kChars - 1)];
          break;
        }
        case 1:
          s.erase(at, 1 + below(64));
          break;
        case 2:
          s.insert(at, s.substr(below(s.size()), 1 + below(64)));
          break;
        case 3:
          s.resize(at);
          break;
        case 4: {  // a number replaced by an extreme one
          const size_t d = s.find_first_of("0123456789", at);
          if (d == std::string::npos) break;
          const size_t end = s.find_first_not_of("0123456789.e-+", d);
          static const char* kNumbers[] = {"0",      "-1",  "1e308", "-1e308",
                                           "1e-320", "nan", "inf",   "2147483648",
                                           "1000",   "1e6", "0.5",   "99999999999999999999999"};
          s.replace(d, end == std::string::npos ? std::string::npos : end - d,
                    kNumbers[below(std::size(kNumbers))]);
          break;
        }
        case 5:  // a span moved elsewhere
        {
          const size_t n = 1 + below(32);
          const std::string span = s.substr(at, n);
          s.erase(at, n);
          s.insert(below(s.size() + 1), span);
          break;
        }
        default:
          s[at] = static_cast<char>(rng_());
      }
    }
    return s;
  }

 private:
  uint64_t below(uint64_t n) { return n ? rng_() % n : 0; }
  std::mt19937_64 rng_;
};

// The refusal is the reader's own type with one line starting with the source name.
void expect_clean(const std::string& what, const std::string& source, const std::string& input) {
  const bool control = std::any_of(what.begin(), what.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
  });
  EXPECT_FALSE(control) << "a line-breaking character in: " << what;
  EXPECT_EQ(what.rfind(source, 0), 0u) << what << "\ninput:\n" << input.substr(0, 2000);
}

template <class Error, class Parse>
void fuzz(const std::string& valid, const std::string& source, uint64_t seed, int cases,
          const Parse& parse) {
  Mutator mutate(seed);
  int refused = 0;
  for (int k = 0; k < cases; ++k) {
    const std::string input = mutate(valid);
    SCOPED_TRACE(source + " case " + std::to_string(k));
    try {
      parse(input);
    } catch (const Error& e) {
      ++refused;
      expect_clean(e.what(), source, input);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a " << typeid(Error).name() << ": " << typeid(e).name() << ": "
                    << e.what() << "\ninput:\n"
                    << input.substr(0, 2000);
    }
  }
  EXPECT_GT(refused, cases / 4);  // the damage is real: most inputs are refused
}

TEST(FuzzInputs, VxaReader) {
  const std::string valid = read_file(testing::data_dir() + "/vxa/walker-stress.vxa");
  ASSERT_FALSE(valid.empty());
  fuzz<VxaError>(valid, "fuzz.vxa", 14001, 400, [](const std::string& text) {
    const VxaRobot v = parse_vxa(text, "fuzz.vxa");
    for (const std::string& w : v.warnings) expect_clean(w, "fuzz.vxa", text);
    try {
      compile(v.robot, v.physics);  // the life bounds: std::invalid_argument, one line
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  });
}

TEST(FuzzInputs, RobotJsonReader) {
  const PhysicsDef physics = preset_gecco2018_code();
  const std::string valid = robot_to_json(demo_walker(), &physics);
  fuzz<InputError>(valid, "fuzz.json", 14002, 400, [](const std::string& text) {
    const RobotFile f = parse_robot_json(text, "fuzz.json");
    try {
      compile(f.robot, f.physics);
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  });
}

TEST(FuzzInputs, ConfigReaders) {
  fuzz<InputError>(evo::default_config_text(), "fuzz-config.json", 14003, 300,
                   [](const std::string& text) { evo::parse_config(text, "fuzz-config.json"); });
  fuzz<InputError>(experiment::preset_text("tiny"), "fuzz-experiment.json", 14004, 300,
                   [](const std::string& text) {
                     experiment::parse_experiment_config(text, "fuzz-experiment.json");
                   });
}

// Nesting and trailing bytes (issue 40): a robot file of 100 000 nested arrays (about 200 kB)
// took 2 GB, growing with the square of the depth; valid JSON followed by a NUL byte and more
// was accepted, the parser stopping at the NUL. Both are refused at once, naming the file.
TEST(FuzzInputs, DeepNestingAndNulBytesAreRefusedCheaply) {
  const auto error = [](const std::string& text) {
    try {
      parse_robot_json(text, "deep.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_EQ(error(deep), "deep.json: (file): nested deeper than 32 levels of objects and arrays");
  const std::string in_physics = R"({"format": "plastivox-robot", "physics": {"a": )" +
                                 std::string(40, '[') + std::string(40, ']') + "}}";
  EXPECT_EQ(error(in_physics),
            "deep.json: physics.a: nested deeper than 32 levels of objects and arrays");
  const PhysicsDef physics = preset_gecco2018_code();
  std::string nul = robot_to_json(demo_walker(), &physics);
  const size_t at = nul.size();
  nul += std::string(1, '\0') + std::string(1000, '\0');
  EXPECT_EQ(error(nul),
            "deep.json: (file): not valid JSON: a NUL byte at offset " + std::to_string(at));
  // 32 levels are fine (the formats need 4).
  EXPECT_NO_THROW(parse_json_input(std::string(32, '[') + std::string(32, ']'), "ok.json"));
}

// Reading grows linearly with the input (issue 40: 400 000 loads took 75 s, quadratic in
// nlohmann's callback parser). Four times the loads may cost at most eight times the CPU time
// (quadratic: sixteen); the best of three runs each, so a busy machine does not decide it.
TEST(FuzzInputs, RobotFileReadingIsLinearInItsLoads) {
  const auto robot_with = [](int loads) {
    std::string text = R"({"format": "plastivox-robot", "version": 1,
      "lattice": {"nx": 2, "ny": 1, "nz": 1, "voxel_size": 0.01},
      "voxels": [[0, 0, 0, 1e9, 0, 0], [1, 0, 0, 1e9, 0, 0]], "loads": [)";
    for (int k = 0; k < loads; ++k) text += R"({"at": [0, 0, 0], "force": [0, 0, 1]},)";
    text.back() = ']';
    return text + "}";
  };
  const auto cpu_seconds = [](const std::string& text) {
    double best = 1e9;
    for (int k = 0; k < 3; ++k) {
      const std::clock_t t0 = std::clock();
      EXPECT_EQ(parse_robot_json(text, "loads.json").robot.loads.size() > 0, true);
      best = std::min(best, static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC);
    }
    return best;
  };
  const double small = cpu_seconds(robot_with(20000)), large = cpu_seconds(robot_with(80000));
  EXPECT_LT(large, 8 * small + 0.05)
      << small << " s for 20 000 loads, " << large << " s for 80 000";
}

// VXA text (issue 40): 200 000 attributes on one element took 81 s in the XML parser, and
// 200 000 distinct unknown tags 28 s (a linear search per tag). Attributes past 64 on one
// element are refused before parsing; unknown tags cost linear time (the same ratio rule as
// the loads above).
TEST(FuzzInputs, VxaAttributesAreBoundedAndUnknownTagsLinear) {
  const std::string valid = read_file(testing::data_dir() + "/vxa/walker-stress.vxa");
  std::string attrs;
  for (int k = 0; k < 100000; ++k) attrs += " a" + std::to_string(k) + "=\"1\"";
  std::string many = valid;
  many.insert(many.find("<VXA") + 4, attrs);
  try {
    parse_vxa(many, "attrs.vxa");
    ADD_FAILURE() << "accepted";
  } catch (const VxaError& e) {
    EXPECT_EQ(std::string(e.what()),
              "attrs.vxa: an element has 100001 attributes, more than the 64 a VXA file can need");
  }
  const auto with_tags = [&](int n) {
    std::string tags;
    for (int k = 0; k < n; ++k) tags += "<T" + std::to_string(k) + "/>";
    std::string text = valid;
    text.insert(text.rfind("</VXA>"), tags);
    return text;
  };
  const auto cpu_seconds = [](const std::string& text) {
    double best = 1e9;
    for (int k = 0; k < 3; ++k) {
      const std::clock_t t0 = std::clock();
      EXPECT_GT(parse_vxa(text, "tags.vxa").warnings.size(), 1000u);
      best = std::min(best, static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC);
    }
    return best;
  };
  const double small = cpu_seconds(with_tags(10000)), large = cpu_seconds(with_tags(40000));
  EXPECT_LT(large, 8 * small + 0.05) << small << " s for 10 000 tags, " << large << " s for 40 000";
}

class FuzzResults : public testing::ScratchDirTest {};

TEST_F(FuzzResults, ResultsReader) {
  evo::EvolveConfig c = evo::parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
    "population": 4, "generations": 1, "lattice": {"nx": 3, "ny": 3, "nz": 3},
    "physics": {"duration": 0.1, "settle_time": 0.05}})",
                                          "tiny");
  evo::RunOptions opt;
  opt.threads = 1;
  evo::run_evolution(c, path("r.h5"), opt);
  const std::string valid = read_file(path("r.h5"));
  ASSERT_GT(valid.size(), 1000u);
  const std::string damaged = path("d.h5");
  fuzz<ResultsError>(valid, damaged, 14005, 200, [&](const std::string& bytes) {
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    evo::read_results(damaged);
  });
  // Unsealed (issue 54): a results file is never read without its seal, cut off or zeroed, so
  // HDF5 never parses a damaged one (unlike a recorded life, UnsealedRecordedLifeReader).
  const auto refusal = [&](const std::string& bytes) {
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    try {
      evo::read_results(damaged);
    } catch (const ResultsError& e) {
      return std::string(e.what());
    }
    return std::string("(read)");
  };
  EXPECT_EQ(refusal(valid.substr(512)),
            damaged + ": an HDF5 file, but not a plastivox evolution results file");
  EXPECT_EQ(
      refusal(std::string(512, '\0') + valid.substr(512)),
      damaged + ": not a plastivox evolution results file (not HDF5, or its header is damaged)");
}

// Recorded lives (issue 40): one flipped bit or one changed metadata byte crashed HDF5 1.10
// inside a string attribute's read, taking `render`, `video`, `view` and Python down. A life
// is now sealed and checked whole before HDF5 sees it: every damaged copy (the text damage
// above, and 200 single bit flips anywhere) is refused with one line, and the binary's
// `render` of a few of them exits 1 with one error line, never a signal.
TEST_F(FuzzResults, RecordedLifeReader) {
  std::string robot = robot_to_json(demo_walker());
  robot.insert(robot.rfind('}'), R"(, "physics": {"duration": 0.3, "settle_time": 0.1})");
  std::ofstream(path("w.json"), std::ios::binary) << robot;
  ASSERT_EQ(testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + path("w.json") +
                           " --record " + path("life.h5") + " --fps 20 2>&1")
                .status,
            0);
  const std::string valid = read_file(path("life.h5"));
  ASSERT_GT(valid.size(), 1000u);
  ASSERT_NO_THROW(read_life_file(path("life.h5")));
  const std::string damaged = path("d.h5");
  fuzz<ResultsError>(valid, damaged, 14008, 150, [&](const std::string& bytes) {
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    read_life_file(damaged);
  });
  std::mt19937_64 rng(14009);
  int refused = 0;
  for (int k = 0; k < 200; ++k) {
    std::string bytes = valid;
    const size_t at = rng() % bytes.size();
    bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8)));
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    try {
      read_life_file(damaged);
    } catch (const ResultsError& e) {
      ++refused;
      expect_clean(e.what(), damaged, "(bit " + std::to_string(at) + ")");
    }
  }
  EXPECT_GT(refused, 150);  // all but flips in the seal's zero padding
  for (int k = 0; k < 3; ++k) {
    std::string bytes = valid;
    bytes[600 + 97 * k] = static_cast<char>(bytes[600 + 97 * k] ^ 0x10);
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    const testing::Output o = testing::shell(std::string(PLASTIVOX_CLI) + " render " + damaged +
                                             " --out " + path("f.png") + " 2>&1");
    EXPECT_EQ(o.status, 1) << o.out;
    EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
    EXPECT_NE(o.out.find("corrupt"), std::string::npos) << o.out;
  }
}

// Unsealed lives (issue 54): a life without a seal (written before seals, 2026-12-05, or with
// its seal cut off) still crashed HDF5 when damaged: SIGSEGV in H5HG_read under a string
// attribute's read (2 of 372 such lives in the hostile run), and a changed byte in a global
// heap's size made it loop for ever. Such a life is now read in a child process first
// (child_read.hpp): every damaged copy reads, or is refused with one line naming the file.
// Each case runs in a child process of its own here too, so a crash fails this test instead
// of ending it: the heap's size byte, then single bit flips in the global heap (the strings of
// every attribute), in the rest of the metadata (object headers, attribute messages) and
// anywhere. PLASTIVOX_FUZZ_CASES=N runs N random flips instead of 150, by hand (2000 passed in
// 27 s of CPU time, 11 min of wall time on a 2-core machine at load 20).
TEST_F(FuzzResults, UnsealedRecordedLifeReader) {
  // A short life of a small body, as in the hostile run: 4 voxels, 0.3 s at 10 fps (11 kB).
  write("small.json", R"({"format": "plastivox-robot", "version": 1,
    "lattice": {"nx": 2, "ny": 2, "nz": 1, "voxel_size": 0.01},
    "voxels": [[0,0,0,1e9,0,0], [1,0,0,1e9,0,0.5], [0,1,0,1e9,0,0], [1,1,0,1e9,0,0.5]]})");
  ASSERT_EQ(testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + path("small.json") +
                           " --preset gecco2018-code --duration 0.3 --record " + path("life.h5") +
                           " --fps 10 2>&1")
                .status,
            0);
  const std::string sealed = read_file(path("life.h5"));
  ASSERT_GT(sealed.size(), 1000u);
  const std::string valid = sealed.substr(512);  // the seal cut off: an unsealed life
  const std::string damaged = path("u.h5");
  std::ofstream(damaged, std::ios::binary | std::ios::trunc) << valid;
  ASSERT_TRUE(is_life_file(damaged));
  const RecordedLife expected = read_life_file(damaged);  // unsealed lives are still read
  ASSERT_GE(expected.result.recording.frames.size(), 4u);

  // One case: read in a child process; a crash there is this test's failure, not its end.
  int refused = 0, cases = 0;
  const auto read_damaged = [&](const std::string& bytes, const std::string& what) {
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
    ++cases;
    const ChildRead r = run_in_child(
        [&] {
          try {
            read_life_file(damaged);
          } catch (const ResultsError&) {
            throw;
          } catch (const std::exception& e) {
            throw std::runtime_error(std::string("not a ResultsError: ") + e.what());
          }
        },
        60);
    if (r.outcome == ChildRead::Outcome::kError) {
      ++refused;
      expect_clean(r.message, damaged, what);
    }
    EXPECT_TRUE(r.outcome == ChildRead::Outcome::kOk || r.outcome == ChildRead::Outcome::kError)
        << what << ": " << r.message;
  };
  const auto flipped = [&](size_t at, int mask) {
    std::string bytes = valid;
    bytes[at] = static_cast<char>(bytes[at] ^ mask);
    return bytes;
  };
  // HDF5 keeps every variable-length string in global heap collections ("GCOL").
  std::vector<size_t> heaps;
  for (size_t at = valid.find("GCOL"); at != std::string::npos; at = valid.find("GCOL", at + 1))
    heaps.push_back(at);
  ASSERT_FALSE(heaps.empty());
  // The collection's size with its low byte changed: HDF5 1.10 looped for ever (the child's
  // CPU limit ends it); through the binary that is one line and exit 1, a second later.
  read_damaged(flipped(heaps[0] + 8, 0xff), "heap size");
  EXPECT_EQ(refused, 1);
  const testing::Output o = testing::shell(std::string(PLASTIVOX_CLI) + " render " + damaged +
                                           " --out " + path("f.png") + " 2>&1");
  EXPECT_EQ(o.status, 1) << o.out;
  EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
  EXPECT_NE(o.out.find(": corrupt (reading it in a separate process ended by"), std::string::npos)
      << o.out;

  const char* env = std::getenv("PLASTIVOX_FUZZ_CASES");
  const int random_cases = env ? std::max(1, std::atoi(env)) : 150;
  std::mt19937_64 rng(54001);
  for (int k = 0; k < random_cases; ++k) {
    // A third in a global heap's first 256 bytes (its header and the strings' headers), a
    // third in the first 2 kB (superblock, root object header, attribute messages), a third
    // anywhere.
    const size_t heap = heaps[rng() % heaps.size()];
    const size_t at = k % 3 == 0   ? heap + rng() % 256
                      : k % 3 == 1 ? rng() % std::min<size_t>(2048, valid.size())
                                   : rng() % valid.size();
    const int bit = static_cast<int>(rng() % 8);
    read_damaged(flipped(std::min(at, valid.size() - 1), 1 << bit),
                 "(bit " + std::to_string(bit) + " of byte " + std::to_string(at) + ")");
  }
  EXPECT_GT(refused, cases / 4);  // the damage is real
}

// The child process behind unsealed lives (child_read.hpp): a crash, a loop and an exception in
// it are outcomes here, never the end of this process. (The SIGSEGV the hostile run saw in
// H5HG_read did not recur in this build's 3000 random bit flips of an unsealed life, which
// found 7 endless loops; a crash is made here directly.)
TEST(ChildRead, ACrashALoopAndAnErrorAreOutcomes) {
  EXPECT_EQ(run_in_child([] {}, 1).outcome, ChildRead::Outcome::kOk);
  const ChildRead segv = run_in_child([] { std::raise(SIGSEGV); }, 1);
  EXPECT_EQ(segv.outcome, ChildRead::Outcome::kCrashed);
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer catches the signal, reports it and ends the child with a status.
  EXPECT_EQ(segv.message.rfind("exit status ", 0), 0u) << segv.message;
#else
  EXPECT_EQ(segv.message.rfind("signal " + std::to_string(SIGSEGV) + " (", 0), 0u) << segv.message;
#endif
  const ChildRead loop = run_in_child(
      [] {
        std::atomic<uint64_t> spins{0};
        for (;;) spins.fetch_add(1, std::memory_order_relaxed);
      },
      1);
  EXPECT_EQ(loop.outcome, ChildRead::Outcome::kCrashed);
  EXPECT_EQ(loop.message.rfind("signal " + std::to_string(SIGXCPU) + " (", 0), 0u) << loop.message;
  // A child that blocks (a lock copied held by the fork) uses no CPU: the wall-clock alarm
  // ends it (20 s for a 1 s CPU limit).
  const ChildRead blocked = run_in_child([] { ::pause(); }, 1);
  EXPECT_EQ(blocked.outcome, ChildRead::Outcome::kCrashed);
  EXPECT_EQ(blocked.message.rfind("signal " + std::to_string(SIGALRM) + " (", 0), 0u)
      << blocked.message;
  const ChildRead error = run_in_child([] { throw ResultsError("x.h5: /@robot: missing"); }, 1);
  EXPECT_EQ(error.outcome, ChildRead::Outcome::kError);
  EXPECT_EQ(error.message, "x.h5: /@robot: missing");
}

// Through the binary: exit 0, 1 or 3 (a damaged file can still be a valid robot, or go
// unstable), never a signal; on exit 1 exactly one error line; every line the command's own.
TEST_F(FuzzResults, SimulateCommand) {
  const PhysicsDef physics = preset_gecco2018_code();
  const struct {
    std::string valid, name;
    uint64_t seed;
  } inputs[] = {{read_file(testing::data_dir() + "/vxa/walker-stress.vxa"), "f.vxa", 14006},
                {robot_to_json(demo_walker(), &physics), "f.json", 14007}};
  for (const auto& in : inputs) {
    Mutator mutate(in.seed);
    for (int k = 0; k < 6; ++k) {
      std::ofstream(path(in.name), std::ios::binary | std::ios::trunc) << mutate(in.valid);
      // A valid damaged robot runs at most 2000 steps (or is refused by that limit).
      const testing::Output o =
          testing::shell("PLASTIVOX_MAX_STEPS=2000 " + std::string(PLASTIVOX_CLI) + " simulate " +
                         path(in.name) + " 2>&1 >/dev/null");
      SCOPED_TRACE(in.name + " case " + std::to_string(k) + ": " + o.out);
      EXPECT_TRUE(o.status == 0 || o.status == 1 || o.status == 3) << o.status;
      size_t errors = 0, start = 0;
      while (start < o.out.size()) {
        const size_t end = o.out.find('\n', start);
        const std::string line = o.out.substr(start, end - start);
        EXPECT_EQ(line.rfind("plastivox simulate: ", 0), 0u) << line;
        errors += line.rfind("plastivox simulate: error: ", 0) == 0;
        start = end == std::string::npos ? o.out.size() : end + 1;
      }
      EXPECT_EQ(errors, o.status == 1 ? 1u : 0u);
    }
  }
}

}  // namespace
}  // namespace plastivox
