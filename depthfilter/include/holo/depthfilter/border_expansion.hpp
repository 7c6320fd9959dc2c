// Border expansion of the foreground (paper Sec. 3.3): pixels just outside the foreground mask
// phi_i whose blurred mask value lies in (0, 1) join the point cloud with that value as their
// weight, so reflections of visitors fade out instead of ending in a hard silhouette. The blurred
// mask is the top level of a `levels`-deep Gaussian pyramid of phi_i brought back to full size.
// Their depth is either the paper's d_bor, the mean filtered depth over the foreground's edge
// pixels, or (the paper's proposed improvement, our default) the depth of the nearest foreground
// pixel with a valid depth, which keeps two visitors at different distances apart.
// Units: metres. Invariant: weight is 0 or in (0, 1); where the weight is positive, the depth is
// positive and finite; both are 0 inside phi_i.
#pragma once

#include <opencv2/core.hpp>

#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {

enum class BorderDepth { MeanEdge, Nearest };

struct BorderExpansionConfig {
  int levels = 3;  // blur pyramid depth; 0 disables the expansion. Border ~ 2^levels pixels wide
  BorderDepth depth = BorderDepth::Nearest;
  float min_weight = 1.0f / 255.0f;  // smaller blurred values are treated as 0
};

struct BorderLayer {
  cv::Mat weight;  // CV_32FC1
  cv::Mat depth;   // CV_32FC1, metres
};

// mask: CV_8UC1 (non-zero = foreground); depth: CV_32FC1 filtered foreground depth (0 = none).
// An empty mask or a mask without any valid depth gives an all-zero layer.
BorderLayer expandBorder(const cv::Mat& mask, const cv::Mat& depth, const BorderExpansionConfig& config);
// The same layer in images from `weight_image` and `depth_image` (buffers reused from frame to frame
// when nobody holds the last layer; see ReusedZeroImage).
BorderLayer expandBorder(const cv::Mat& mask, const cv::Mat& depth, const BorderExpansionConfig& config,
                         ReusedZeroImage& weight_image, ReusedZeroImage& depth_image);

// The mask's bounding box grown by the blur's reach (clipped to the image; empty for an empty
// mask): the layer's weight is 0 outside it, and the mask lies inside it.
cv::Rect borderBox(const cv::Mat& mask, const BorderExpansionConfig& config);

}  // namespace holo::depthfilter
