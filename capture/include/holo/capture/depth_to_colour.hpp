// Depth from a second device, reprojected into the colour image: a camera whose colour and depth
// come from two devices (two sensors side by side, each with its own lens) delivers depth in the
// depth sensor's geometry; the foreground pipeline needs it per colour pixel. Each valid depth
// pixel is back-projected with the depth intrinsics (undistorted), moved into the colour camera's
// frame by T_colour_depth (the calibration's depth registration) and projected with the colour
// intrinsics (distorted); the nearest surface wins where several land on one pixel. A depth
// pixel is splatted onto the 2x2 colour pixels around where it lands, so a colour image up to
// twice as fine as the depth has no holes from the resampling itself.
// Output: CV_32FC1, the colour image's size, metres along the colour camera's axis, 0 = none.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/core/camera_model.hpp"

namespace holo::capture {

class DepthToColour {
 public:
  DepthToColour() = default;
  // Throws InputError when either intrinsics has a non-positive size.
  DepthToColour(const Intrinsics& depth, const Intrinsics& colour, const mat4& T_colour_depth);

  // `depth`: CV_32FC1 metres of the depth intrinsics' size; throws holo::Error otherwise.
  cv::Mat apply(const cv::Mat& depth) const;
  cv::Size depthSize() const { return {depth_.width, depth_.height}; }
  cv::Size colourSize() const { return {colour_.width(), colour_.height()}; }

 private:
  Intrinsics depth_;
  CameraModel colour_;
  mat4 T_colour_depth_{1.0f};
  std::vector<vec3> directions_;  // depth pixels' z = 1 rays, row-major
};

}  // namespace holo::capture
