#include "experiment_run.hpp"
namespace plastivox::experiment {
std::vector<std::string> stage_rendering(StageContext& ctx) {
  ctx.progress.log("[rendering] pending");
  return {};
}
}  // namespace plastivox::experiment
