// Baseline temporal depth filters, for comparison with the pull-push filter only (paper Sec.
// 4.1.3): a per-pixel temporal median (FPCG_mf) and TAA-style exponential blending with
// neighbourhood clamping (FPCG_taa). Both see the same inputs as TemporalDepthFilter (foreground
// mask, depth and the precursor flow, so history follows the moving content as TAA's
// reprojection does) and output depth only on the foreground. Units: metres, 0 = invalid.
// Invariant: outputs are finite, 0 outside the mask.
#pragma once

#include <deque>
#include <opencv2/core.hpp>

#include "holo/depthfilter/temporal_depth_filter.hpp"

namespace holo::eval {

// Median of the pixel's valid depths over the last `window` frames (same pixel, no motion
// compensation, as a per-pixel temporal median filter is usually run on depth streams).
class TemporalMedianDepthFilter {
 public:
  explicit TemporalMedianDepthFilter(int window = 5);
  cv::Mat apply(const depthfilter::DepthFilterInput& input);

 private:
  int window_;
  std::deque<cv::Mat> history_;  // raw sanitised depth, newest last
};

// history' = clamp(history(px_pre), min, max of the current 3x3 valid neighbourhood);
// out = blend * current + (1 - blend) * history'. Holes take the clamped history.
class TaaDepthFilter {
 public:
  explicit TaaDepthFilter(float blend = 0.1f);
  cv::Mat apply(const depthfilter::DepthFilterInput& input);

 private:
  float blend_;
  cv::Mat history_;  // previous output
};

}  // namespace holo::eval
