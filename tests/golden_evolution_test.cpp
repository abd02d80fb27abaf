// Golden bits of evolution: the content digest of a tiny run per treatment, and the byte
// serialisation of a run's identity (config and resolved physics), fixed here as main at
// 22a63f5 produced them on 2026-12-02. A content digest is about science, not layout: moving
// a field between structs or renaming one in the code must not change it. A commit that
// changes a value here must say why in its message.
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "plastivox/evo/eval_pool.hpp"
#include "plastivox/evo/evolver.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

// 5x5x5 lattice, population 6, 3 generations after the first, 0.5 s lives (0.3 s of
// walking and development after settling).
EvolveConfig tiny(Treatment t) {
  EvolveConfig c = parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 3, "population": 6, "generations": 3, "lattice": {"nx": 5, "ny": 5, "nz": 5},
      "physics": {"duration": 0.5, "settle_time": 0.2}})",
                                "golden");
  c.treatment = t;
  c.physics.treatment = t;
  return c;
}

std::string evolved_digest(Treatment t, int threads) {
  Evolver ev(Evolver::new_run(tiny(t)), threads);
  while (!ev.finished()) ev.step();
  return content_digest(ev.state()).hex();
}

struct GoldenRun {
  Treatment treatment;
  const char* digest;
};

const GoldenRun kRuns[] = {
    {Treatment::kNone, "c96a412ce9ee6a25a301407de2359b98"},
    {Treatment::kStress, "7e9bf1c5393272367762efe23c448e1d"},
    {Treatment::kPressure, "95c4c030b7c4afc22e74f07bd372c002"},
};

TEST(GoldenEvolution, TinyRunDigestPerTreatmentOnOneAndTwoThreads) {
  for (const GoldenRun& g : kRuns)
    for (int threads : {1, 2})
      EXPECT_EQ(evolved_digest(g.treatment, threads), g.digest)
          << to_string(g.treatment) << " on " << threads << " thread" << (threads == 1 ? "" : "s");
}

// The three runs at once, their candidates in one evaluation pool (as `plastivox experiment`
// evolves): each run still gives its golden digest.
TEST(GoldenEvolution, RunsSharingOneEvaluationPoolKeepTheirDigests) {
  for (int threads : {1, 2}) {
    EvaluationPool pool(threads);
    std::vector<std::string> digests(std::size(kRuns));
    std::vector<std::thread> drivers;
    for (size_t r = 0; r < std::size(kRuns); ++r)
      drivers.emplace_back([&, r] {
        Evolver ev(Evolver::new_run(tiny(kRuns[r].treatment)), 1, &pool);
        while (!ev.finished()) ev.step();
        digests[r] = content_digest(ev.state()).hex();
      });
    for (std::thread& d : drivers) d.join();
    for (size_t r = 0; r < std::size(kRuns); ++r)
      EXPECT_EQ(digests[r], kRuns[r].digest)
          << to_string(kRuns[r].treatment) << " on a pool of " << threads;
  }
}

// The identity a results file is matched and digested by, byte for byte.
TEST(GoldenEvolution, IdentitySerialisationIsByteStable) {
  const EvolveConfig c = tiny(Treatment::kStress);
  EXPECT_EQ(
      c.identity_json(),
      R"({"format":"plastivox-evolve-config","generations":3,"geometry":"largest-component",)"
      R"("lattice":{"nx":5,"ny":5,"nz":5,"voxel_size":0.01},"max_mutation_tries":1500,)"
      R"("min_fill":0.2,"physics":{"duration":0.5,"settle_time":0.2},"population":6,"seed":3,)"
      R"("treatment":"stress","version":1})");
  EXPECT_EQ(resolved_physics_json(c.physics),
            R"({"act_amplitude":0.1447,"act_frequency":5.0,"act_min_factor":0.1,)"
            R"("axial_modulus":"harmonic","bond_damping":1.0,"bond_model":"exact",)"
            R"("collision_damping":0.8,"collision_exclude_hops":3,"contact_diameter":1.5,)"
            R"("density":1000000000.0,"dt_frac":0.9,"duration":0.5,"e_max":100000000000.0,)"
            R"("e_min":100000.0,"fitness":"3d","floor":true,"global_damping":0.01,)"
            R"("global_damping_rot_factor":10.0,"gravity":-9.81,"growth":"integral",)"
            R"("max_change_per_step":1000000000.0,"max_speed":100.0,"min_devo_factor":1000.0,)"
            R"("mu_kinetic":0.5,"mu_static":1.0,"poisson":0.35,"record_fps":0.0,)"
            R"("self_collision":true,"settle_time":0.2,"treatment":"stress"})");
  EXPECT_EQ(EvolveConfig().identity_json(),
            R"({"format":"plastivox-evolve-config","generations":5000,)"
            R"("geometry":"largest-component","lattice":{"nx":10,"ny":10,"nz":10,)"
            R"("voxel_size":0.01},"max_mutation_tries":1500,"min_fill":0.2,)"
            R"("physics":{"preset":"gecco2018-code"},"population":24,"seed":1,"treatment":"none",)"
            R"("version":1})");
  EXPECT_EQ(resolved_physics_json(preset_gecco2018_paper()),
            R"({"act_amplitude":0.1447,"act_frequency":5.0,"act_min_factor":0.1,)"
            R"("axial_modulus":"harmonic","bond_damping":1.0,"bond_model":"exact",)"
            R"("collision_damping":0.8,"collision_exclude_hops":3,"contact_diameter":1.5,)"
            R"("density":1000000000.0,"dt_frac":0.9,"duration":5.2,"e_max":10000000000.0,)"
            R"("e_min":10000.0,"fitness":"xy","floor":true,"global_damping":0.01,)"
            R"("global_damping_rot_factor":10.0,"gravity":-9.81,"growth":"rate",)"
            R"("max_change_per_step":1000000000.0,"max_speed":100.0,"min_devo_factor":1000.0,)"
            R"("mu_kinetic":0.5,"mu_static":1.0,"poisson":0.35,"record_fps":0.0,)"
            R"("self_collision":true,"settle_time":0.2,"treatment":"none"})");
}

}  // namespace
}  // namespace plastivox::evo
