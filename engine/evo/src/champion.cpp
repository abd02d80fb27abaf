#include "plastivox/evo/champion.hpp"

#include "plastivox/base/error.hpp"  // InputError

namespace plastivox::evo {

const ChampionRecord& champion_at(const RunState& run, int generation, const std::string& source) {
  if (run.generations_done < 0)
    throw InputError(source + ": no generation evaluated yet, so no champion");
  if (generation < 0) generation = run.generations_done;
  if (generation > run.generations_done)
    throw InputError(source + ": generation " + std::to_string(generation) + " is beyond the " +
                     std::to_string(run.generations_done) + " generations done");
  const ChampionRecord* champion = nullptr;
  for (const ChampionRecord& c : run.champions)
    if (c.generation <= generation) champion = &c;
  if (!champion)
    throw InputError(source + ": champions: none recorded by generation " +
                     std::to_string(generation));
  return *champion;
}

RobotDef champion_robot(const ChampionRecord& champion, int generation) {
  RobotDef robot = champion.phenotype;
  robot.name = "champion-" + std::to_string(champion.id) + "-gen" + std::to_string(generation);
  return robot;
}

}  // namespace plastivox::evo
