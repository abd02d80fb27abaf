#include "experiment_run.hpp"
namespace plastivox::experiment {
std::vector<std::string> stage_analysis(StageContext& ctx) {
  ctx.progress.log("[analysis] pending");
  return {};
}
}  // namespace plastivox::experiment
