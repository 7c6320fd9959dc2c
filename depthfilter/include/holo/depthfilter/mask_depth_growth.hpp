// The foreground mask grown into readings whose background depth is unknown. Where the empty hall
// read nothing (the floor at a grazing angle, the hall beyond the sensor's range) the mask has no
// depth to compare a live reading with, and only the colour labels decide; a visitor whose colour
// matches the hall there is lost although the sensor reads them. Such a reading joins the mask
// when it touches the mask (4-connected) and its depth lies within the margin of a touching mask
// pixel's reading: the same surface continues. Each step grows the mask by one pixel, so a hall
// reading that continues a visitor's surface (the floor at the feet) joins by at most `steps`
// pixels; readings with a known background depth are left to the depth comparison.
#pragma once

#include <opencv2/core.hpp>

namespace holo::depthfilter {

struct MaskDepthGrowthConfig {
  static constexpr int kMaxSteps = 16;
  int steps = 0;                    // pixels of growth, 0..kMaxSteps (0: off)
  float depth_margin_m = 0.04f;     // the surface's continuity: |d - d_neighbour| <= m + z2 * d^2
  float depth_margin_z2 = 0.0075f;  // 1/metres
};

// Grows `mask` (CV_8UC1, 255 = foreground) in place into pixels of `depth` (CV_32FC1 metres, 0 or
// NaN = no reading) where `background_depth` (CV_32FC1, 0 = unknown) is unknown. `scratch` is
// reused between calls. Throws holo::Error when the images' sizes or types disagree.
void growMaskIntoUnknownBackground(cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const MaskDepthGrowthConfig& config, cv::Mat& scratch);

}  // namespace holo::depthfilter
