// The foreground at the camera's resolution from one computed on frames reduced by an integer
// scale (foreground_scale.hpp): the reduced mask and filtered depth decide the interior, the
// camera's own depth readings decide the outline.
//
// A reduced pixel (block) whose 3x3 neighbourhood of blocks is all foreground or all background
// is repeated over its block, as expandedToFull does. On an outline block (a neighbour differs),
// a camera pixel whose valid reading z is not clearly in front of the block's background depth
// (the mask's own depth test: z >= background - margin(background)) is background; otherwise
// it is foreground iff some foreground block of the
// neighbourhood has a filtered depth within margin(z) = depth_margin_m + depth_margin_z2 * z^2 of
// it (the mask's own "same surface" margin); it takes the nearest such depth, so the output stays
// the filter's (temporally stable) depth. A pixel without a reading, or whose neighbourhood holds
// no filtered depth, keeps its block's mask and depth. So a block the reduced mask took whole
// loses the pixels that read the hall behind the visitor, and a block it left out gains those
// that read the visitor beside it.
// Units: metres. Invariant: depth > 0 only where the mask is 255; both 0 outside the reduced
// mask's box grown by one block.
#pragma once

#include <opencv2/core.hpp>

#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {

struct FullSizeOutlineConfig {
  float depth_margin_m = 0.04f;     // as ForegroundMaskConfig::depth_margin_m
  float depth_margin_z2 = 0.0075f;  // as ForegroundMaskConfig::depth_margin_z2, 1/metres
};

struct FullSizeForeground {
  cv::Mat mask;   // CV_8UC1 at the camera's resolution, 255 = foreground
  cv::Mat depth;  // CV_32FC1 at the camera's resolution, 0 = none
  // CV_8UC1 at the reduced resolution: 255 where the block was redrawn from the readings (an
  // outline or depth-edge block), 0 where it is its reduced pixel repeated.
  cv::Mat redrawn;
};

// mask: CV_8UC1 reduced (non-zero = foreground); depth: CV_32FC1 reduced filtered depth (0 =
// none); background_depth: CV_32FC1 reduced, the mask's learned hall (0 = unknown); camera_depth: CV_32FC1
// the sensor's readings at `scale` times the reduced size (0, NaN or Inf = none). Throws holo::Error on other
// types or sizes.
FullSizeForeground fullSizeOutline(const cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const cv::Mat& camera_depth, int scale,
                                   const FullSizeOutlineConfig& config = {});
// The same in images from `mask_image` and `depth_image` (buffers reused from frame to frame when
// nobody holds the last result; see ReusedZeroImage).
FullSizeForeground fullSizeOutline(const cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const cv::Mat& camera_depth, int scale,
                                   const FullSizeOutlineConfig& config, ReusedZeroImage& mask_image,
                                   ReusedZeroImage& depth_image);

}  // namespace holo::depthfilter
