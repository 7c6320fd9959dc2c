// The foreground at the camera's resolution from one computed on frames reduced by an integer
// scale (foreground_scale.hpp): the reduced mask and filtered depth decide the interior, the
// camera's own depth readings decide the outline.
//
// A reduced pixel (block) is repeated over its block, as expandedToFull does, unless its 3x3
// neighbourhood of blocks holds both foreground and background (an outline block) or foreground
// depths further apart than the margin (a depth-edge block, an arm before the body); margin(z) =
// depth_margin_m + depth_margin_z2 * z^2, the mask's own. There each camera pixel with a valid
// reading z is redrawn: it is the hall where z is not clearly in front of the block's learned
// background (z >= background - margin(background), the mask's depth test); else it takes the
// nearest neighbouring foreground block's filtered depth within margin(z) (the filter's depth,
// temporally stable, not the reading); with none within the margin it is background on an
// outline block and keeps its block's depth on a depth-edge block. A pixel without a reading, or
// whose neighbourhood holds no filtered depth, keeps its block's mask and depth. So a block the
// reduced mask took whole loses the pixels that read the hall behind the visitor, a block it left
// out gains those that read the visitor beside it, and a block across two surfaces splits.
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
