// Edge-aware filtering of what the relic changes on the real surfaces: the composite's change
// (composite - background) at each real pixel (no sample met the relic) is replaced by the
// Gaussian-weighted mean of the changes of its real neighbours on the same surface (valid depth
// within max_depth_ratio of its own), so a delta path tracer's few samples of a soft shadow give
// a smooth one while the relic's silhouette and depth edges stay sharp. Pixels a sample of the
// relic met are left as they are. Units: pixels; depth CV_32FC1 metres, 0 = invalid.
#pragma once

#include <opencv2/core.hpp>

namespace holo::ar {

struct ChangeFilterSettings {
  bool enabled = true;
  int radius = 3;                 // pixels; the window is (2 radius + 1)^2
  float sigma = 2.0f;             // pixels
  float max_depth_ratio = 0.03f;  // neighbours farther in depth than this fraction are another surface
};

// composite, background: CV_32FC3 of one size; relic_coverage CV_32FC1 and depth CV_32FC1 of that
// size. Returns the filtered composite (a copy when disabled).
cv::Mat filterChange(const cv::Mat& composite, const cv::Mat& background, const cv::Mat& relic_coverage,
                     const cv::Mat& depth, const ChangeFilterSettings& settings);

}  // namespace holo::ar
