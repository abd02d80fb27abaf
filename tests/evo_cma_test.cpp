// CMA-ES (docs/evolution.md, "CMA-ES"): the strategy on known quadratics, the algorithm field
// and its refusals, and a run on a fixed body through the evolver's machinery: the same bits
// on any thread count, a resume equal to an uninterrupted run, champions whose robot files
// replay their lives.
#include <cmath>
#include <filesystem>

#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/cma.hpp"
#include "plastivox/evo/cma_body.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

using testing::error_of;
using testing::RelNear;

// Minimises f from x0 with lambda samples a generation; returns the best f seen.
template <class F>
double minimise(F f, std::vector<double> x0, double sigma, bool separable, int generations,
                CmaState* end = nullptr) {
  const int n = static_cast<int>(x0.size());
  const int lambda = cma_default_lambda(n);
  CmaState s = cma_start(x0, sigma, separable);
  double best = f(x0);
  for (int g = 0; g < generations; ++g) {
    const CmaBasis basis = cma_basis(s);
    std::vector<std::vector<double>> xs;
    std::vector<double> fs;
    for (int k = 0; k < lambda; ++k) {
      Rng rng = Rng::stream(7, StreamPurpose::kTest, g, k);
      xs.push_back(cma_sample(s, basis, rng));
      fs.push_back(f(xs.back()));
      best = std::min(best, fs.back());
    }
    std::vector<int> order(lambda);
    for (int k = 0; k < lambda; ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return fs[a] != fs[b] ? fs[a] < fs[b] : a < b; });
    std::vector<const std::vector<double>*> top;
    for (int k = 0; k < lambda / 2; ++k) top.push_back(&xs[order[k]]);
    cma_update(s, basis, top, lambda);
  }
  if (end) *end = s;
  return best;
}

// A correlated quadratic, (x - c)^T (I + 100 1 1^T) (x - c): condition 1 + 100 n, its long
// axis along no coordinate, so only a full covariance learns it.
double correlated(const std::vector<double>& x) {
  double sq = 0, sum = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double d = x[i] - (1.0 + 0.5 * static_cast<double>(i));
    sq += d * d;
    sum += d;
  }
  return sq + 100 * sum * sum;
}

// An axis-parallel ellipsoid, condition 1e3, optimum at x_i = 1 - 0.1 i.
double ellipsoid(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  double f = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double d = x[i] - (1.0 - 0.1 * static_cast<double>(i));
    f += std::pow(1e3, static_cast<double>(i) / (n - 1)) * d * d;
  }
  return f;
}

TEST(CmaCore, FullCovarianceReachesTheOptimumOfACorrelatedQuadratic) {
  CmaState end;
  const double best = minimise(correlated, std::vector<double>(8, 0.0), 1.0, false, 400, &end);
  EXPECT_LT(best, 1e-10);
  for (size_t i = 0; i < end.mean.size(); ++i) EXPECT_NEAR(end.mean[i], 1.0 + 0.5 * i, 1e-4);
  // The same inputs give the same bits.
  CmaState again;
  minimise(correlated, std::vector<double>(8, 0.0), 1.0, false, 400, &again);
  EXPECT_EQ(again, end);
}

TEST(CmaCore, SeparableReachesTheOptimumOfAnEllipsoidInHighDimension) {
  CmaState end;
  const double best = minimise(ellipsoid, std::vector<double>(40, 0.0), 1.0, true, 700, &end);
  EXPECT_LT(best, 1e-8);
  EXPECT_EQ(end.cov.size(), 40u);  // the diagonal alone
}

TEST(CmaCore, TheDefaultsFollowTheTutorial) {
  EXPECT_EQ(cma_default_lambda(95), 4 + 13);  // 4 + floor(3 ln 95) = 4 + 13
  EXPECT_EQ(cma_default_lambda(2), 6);
  EXPECT_THROW(cma_start({}, 1.0, false), std::invalid_argument);
}

// A 3x2x2 block, 5e9 Pa, phases staggered along x, development 0.5/s, and a distributed
// controller (2 hidden units, zero weights) or the sine; as a robot file's JSON object.
std::string body_json(bool neural = true) {
  RobotDef r = make_empty_robot(3, 2, 2);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) {
        const int s = r.site(x, y, z);
        r.present[s] = 1;
        r.stiffness[s] = 5e9;
        r.dev_rate[s] = 0.5;
        r.phase[s] = 0.25 * x;
      }
  if (neural) {
    r.controller.kind = ControllerKind::kDistributed;
    r.controller.hidden = 2;
    r.controller.weights.assign(weight_count(ControllerKind::kDistributed, 2), 0.0);
  }
  r.name = "block";
  return robot_to_json(r);
}

std::string config_text(const std::string& extra) {
  return R"({"format": "plastivox-evolve-config", "version": 1, "seed": 3, "generations": 3,
      "treatment": "stress", "physics": {"duration": 0.4, "settle_time": 0.2})" +
         extra + "}";
}

EvolveConfig tiny(const std::string& genome) {
  return parse_config(config_text(R"(, "algorithm": "cma-es", "genome": ")" + genome +
                                  R"(", "body": )" + body_json(genome == "controller")),
                      "tiny");
}

std::string evolved_digest(const EvolveConfig& c, int threads) {
  Evolver ev(Evolver::new_run(c), threads);
  while (!ev.finished()) ev.step();
  return content_digest(ev.state()).hex();
}

TEST(CmaConfig, TheAlgorithmFieldAndItsRefusals) {
  const auto error = [](const std::string& extra) {
    return error_of([&] { parse_config(config_text(extra), "run.json"); });
  };
  EXPECT_EQ(parse_config(config_text(R"(, "algorithm": "afpo")"), "a").identity_json(),
            parse_config(config_text(""), "b").identity_json());  // afpo is the default
  EXPECT_EQ(error(R"(, "algorithm": "nsga")"),
            "run.json: algorithm: 'nsga' is unknown (use afpo, cma-es or map-elites)");
  EXPECT_EQ(error(R"(, "genome": "phase")"), "run.json: genome: applies to algorithm cma-es only");
  const std::string cma = R"(, "algorithm": "cma-es", "genome": "phase", "body": )" + body_json();
  EXPECT_EQ(error(cma + R"(, "lattice": {"nx": 4})"),
            "run.json: lattice: applies to algorithms afpo and map-elites only (cma-es searches a "
            "genome of its fixed body)");
  EXPECT_EQ(error(cma + R"(, "controller": {"kind": "central"})"),
            "run.json: controller: applies to algorithms afpo and map-elites only (cma-es searches "
            "a genome of its fixed body)");
  EXPECT_EQ(error(R"(, "algorithm": "cma-es", "genome": "phase")"),
            "run.json: body: missing: cma-es needs a fixed body (a robot file or a results file)");
  EXPECT_EQ(error(cma + R"(, "cma": {"sigma": -1})"), "run.json: cma.sigma: must be in (0, 1000]");
  EXPECT_EQ(error(cma + R"(, "cma": {"covariance": "lowrank"})"),
            "run.json: cma.covariance: 'lowrank' is unknown (use auto, full or separable)");
  RobotDef big = make_empty_robot(20, 20, 6);
  big.present.assign(big.sites(), 1);
  big.stiffness.assign(big.sites(), 5e9);
  EXPECT_EQ(error(R"(, "algorithm": "cma-es", "genome": "phase", "cma": {"covariance": "full"},
      "body": )" + robot_to_json(big)),
            "run.json: cma.covariance: full covariance for 2400 numbers is too large (at most "
            "2000); use separable");
  EXPECT_EQ(error(cma + R"(, "population": 1)"),
            "run.json: population: cma-es needs at least 2 samples a generation");
  EXPECT_EQ(error(R"(, "algorithm": "cma-es", "genome": "gait", "body": "x.json")"),
            "run.json: genome: 'gait' is unknown (use controller, phase or materials)");
  EXPECT_NE(error(R"(, "algorithm": "cma-es", "genome": "phase", "body": "/nonexistent.json")")
                .find("run.json: body: "),
            std::string::npos);
  RobotDef sine = parse_robot_json(body_json(), "b").robot;
  sine.controller = ControllerDef{};
  EXPECT_EQ(
      error(R"(, "algorithm": "cma-es", "genome": "controller", "body": )" + robot_to_json(sine)),
      "run.json: genome: controller needs a body with a distributed or central controller "
      "(it runs the sine)");
}

TEST(CmaConfig, EachGenomeSetsItsPartOfTheBody) {
  const EvolveConfig c = tiny("controller");
  EXPECT_EQ(c.algorithm, Algorithm::kCmaEs);
  EXPECT_EQ(c.controller_genes.count, weight_count(ControllerKind::kDistributed, 2));
  EXPECT_EQ(c.population, cma_default_lambda(c.controller_genes.count));
  EXPECT_FALSE(c.cma.separable);
  EXPECT_EQ(parse_config(c.canonical_json(), "again").identity_json(), c.identity_json());
  EXPECT_EQ(genome_dimension(tiny("phase")), 12);
  EXPECT_EQ(genome_dimension(tiny("materials")), 24);  // stiffness and development
  // The start is the body as it is; phases wrap into (-1, 1).
  const EvolveConfig p = tiny("phase");
  const Phenotype same = express_vector(p, genome_start(p));
  EXPECT_EQ(same.robot.phase, p.cma.body.phase);
  std::vector<double> x(12, 1.5);
  EXPECT_EQ(express_vector(p, x).robot.phase[0], -0.5);
  x.assign(12, -0.75);
  EXPECT_EQ(express_vector(p, x).robot.phase[0], -0.75);
  x.assign(12, 3.0);
  EXPECT_EQ(express_vector(p, x).robot.phase[0], 0.0);  // one cycle is none
  const EvolveConfig m = tiny("materials");
  const Phenotype mat = express_vector(m, genome_start(m));
  EXPECT_TRUE(RelNear(mat.robot.stiffness[0], 5e9, 1e-9));
  EXPECT_TRUE(RelNear(mat.robot.dev_rate[0], 0.5, 1e-9));
}

// Golden bits of a tiny CMA-ES run per genome, on one and two threads.
TEST(CmaRun, TinyRunDigestPerGenomeOnOneAndTwoThreads) {
  const std::pair<const char*, const char*> kGolden[] = {
      {"controller", "4312cfe66decca5f0d56e96aaa563a9e"},
      {"phase", "acd887c0a5176c08390072cf70bc0184"},
      {"materials", "872f59af79eca236464515dace44a562"},
  };
  for (const auto& [genome, digest] : kGolden) {
    const EvolveConfig c = tiny(genome);
    const std::string one = evolved_digest(c, 1);
    EXPECT_EQ(one, digest) << genome;
    EXPECT_EQ(evolved_digest(c, 2), one) << genome;
  }
}

TEST(CmaRun, TheSearchImprovesAndTheChampionIsTheBestEver) {
  EvolveConfig c = tiny("phase");
  c.generations = 6;
  Evolver ev(Evolver::new_run(c), 2);
  while (!ev.finished()) ev.step();
  const RunState& s = ev.state();
  double best = -1;
  for (const BirthRecord& b : s.births)
    if (b.status == static_cast<uint8_t>(EvalStatus::kOk)) best = std::max(best, b.fitness);
  EXPECT_EQ(s.champions.back().fitness, best);
  EXPECT_GT(best, s.history[0].fitness[0]);
  EXPECT_EQ(s.population.size(), static_cast<size_t>(c.population));
  EXPECT_EQ(s.cma.updates, 7);
}

class CmaFiles : public testing::ScratchDirTest {};

TEST_F(CmaFiles, StopAndResumeEqualsUninterruptedAndTheChampionReplays) {
  for (const char* genome : {"controller", "materials"}) {
    const EvolveConfig c = tiny(genome);
    const std::string full_path = path(std::string(genome) + "-full.h5");
    const std::string part_path = path(std::string(genome) + "-part.h5");
    const RunReport full = run_evolution(c, full_path, {});
    RunOptions stop;
    stop.stop_after = 1;
    stop.threads = 1;
    EXPECT_EQ(run_evolution(c, part_path, stop).outcome, RunOutcome::kStopped);
    const RunReport rest = run_evolution(c, part_path, {});
    EXPECT_EQ(rest.resumed_from, 1);
    EXPECT_EQ(rest.content_digest, full.content_digest) << genome;

    const ResultsFile f = read_results(part_path);
    EXPECT_EQ(f.state.config.algorithm, Algorithm::kCmaEs);
    EXPECT_EQ(f.state.cma.updates, 4);
    // The champion's robot file is the body with its genome; it replays the evaluated life.
    const ChampionRecord& champ = champion_at(f.state, -1, "part.h5");
    ASSERT_EQ(champ.status, static_cast<uint8_t>(EvalStatus::kOk));
    const RobotDef robot = champion_robot(champ, f.state.generations_done);
    EXPECT_EQ(robot.voxel_count(), 12);
    const RobotFile back = parse_robot_json(robot_to_json(robot, &c.physics), "champion.json");
    EXPECT_EQ(simulate(compile(back.robot, back.physics)).fitness, champ.fitness) << genome;

    // A body taken from this results file: its champion.
    const EvolveConfig from_file = parse_config(
        config_text(R"(, "algorithm": "cma-es", "genome": "phase", "body": ")" + part_path + "\""),
        "again");
    EXPECT_EQ(from_file.cma.body.phase, robot.phase);
    EXPECT_EQ(from_file.cma.body.stiffness, robot.stiffness);
  }
}

// One evaluation pool for a CMA-ES run and an AFPO run at once: each gives its own bits.
TEST_F(CmaFiles, SharingOnePoolWithAnAfpoRunChangesNoBit) {
  EvolveConfig afpo = parse_config(config_text(R"(, "population": 4,
      "lattice": {"nx": 4, "ny": 4, "nz": 4})"),
                                   "afpo");
  afpo.generations = 2;
  const EvolveConfig cma = tiny("materials");
  const std::string alone_afpo = evolved_digest(afpo, 1), alone_cma = evolved_digest(cma, 1);
  ManyRunOptions o;
  o.threads = 2;
  const std::vector<RunReport> r =
      run_evolutions({{afpo, path("afpo.h5")}, {cma, path("cma.h5")}}, o);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].content_digest, alone_afpo);
  EXPECT_EQ(r[1].content_digest, alone_cma);
}

}  // namespace
}  // namespace plastivox::evo
