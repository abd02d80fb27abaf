#include "experiment_run.hpp"
namespace plastivox::experiment {
std::vector<std::string> stage_report(StageContext& ctx, const std::vector<std::string>&) {
  ctx.progress.log("[report] pending");
  return {};
}
}  // namespace plastivox::experiment
