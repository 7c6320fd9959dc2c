#include "holo/eval/acceptance_bars.hpp"

#include <algorithm>

#include "holo/eval/depth_evaluation.hpp"
#include "holo/eval/reflection_flicker.hpp"

namespace holo::eval {

double foregroundBarWithFloor(double reference_fg_mse, double reconstruction_floor) {
  return std::max(reference_fg_mse / kForegroundBelowReference,
                  kReconstructionFloorMargin * std::max(0.0, reconstruction_floor));
}

DepthBarVerdicts checkDepthBars(const DepthMethodMetrics& m, const DepthMethodMetrics& raw,
                                const DepthMethodMetrics& median, const DepthMethodMetrics& taa,
                                const DepthBars& bars) {
  // Written so that a NaN on either side makes the comparison false.
  DepthBarVerdicts v;
  v.below_median = m.temporal_mse_cm2 * bars.below_median <= median.temporal_mse_cm2;
  v.below_taa = m.temporal_mse_cm2 * bars.below_taa <= taa.temporal_mse_cm2;
  v.rmse_below_raw = m.depth_rmse_cm < raw.depth_rmse_cm;
  v.coverage = m.coverage >= bars.coverage;
  v.ghosts = m.ghost_ratio < raw.ghost_ratio && m.ghost_ratio < bars.ghosts;
  return v;
}

FlickerBarVerdicts checkFlickerBars(const ReflectionFlickerMetrics& m, const ReflectionFlickerMetrics& raw,
                                    const ReflectionFlickerMetrics& taa) {
  FlickerBarVerdicts v;
  v.below_raw = m.flicker * kFlickerBelowRaw <= raw.flicker;
  v.below_taa = m.flicker < taa.flicker;
  return v;
}

}  // namespace holo::eval
