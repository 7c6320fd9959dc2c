// A picture of a camera's foreground depth as a point cloud seen from a shifted viewpoint (the
// paper's Fig. 9 moves the viewer 0.8 units back and 0.2 to the side), so depth noise, holes and
// deformation show as scattered, missing or bent points. Points are splatted with a z-buffer and
// coloured by depth (turbo colour map over [near_m, far_m]); the background is black.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"

namespace holo::depthfilter {

// depth: CV_32FC1 metres (0 = no point); shift_camera_m: the viewer's offset in the source
// camera's frame (x right, y down, z forward). Returns CV_8UC3 of the camera's size.
cv::Mat renderShiftedCloud(const cv::Mat& depth, const Intrinsics& intrinsics, const vec3& shift_camera_m,
                           float near_m, float far_m);

}  // namespace holo::depthfilter
