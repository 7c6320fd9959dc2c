// How well a calibrated camera's pose fits what it sees: straight edges of known geometry (a
// printed target's squares, in the pyramid frame) projected through the camera's intrinsics and
// pose, against the edges found in its colour image (Canny). Two figures:
//   chamfer      the mean distance (pixels) from points sampled along the projected edges to the
//                nearest image edge, each truncated at kEdgeTruncationPx; a point that projects
//                outside the image or behind the camera counts as the truncation, so a pose that
//                looks away from the target cannot score well by showing less of it
//   pose error   the smallest change of the camera's pose (position in millimetres, direction in
//                degrees) that brings the projected edges onto the image's edges: Levenberg-
//                Marquardt on the truncated distances from the calibrated pose, i.e. the chamfer
//                converted into how far the pose is off
// Units: metres, pixels, degrees. Deterministic.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"

namespace holo::calib {

// One straight edge of known geometry, world (pyramid) frame, metres.
struct EdgeSegment {
  cv::Point3d a, b;
};

inline constexpr double kEdgeTruncationPx = 8.0;     // farther than this counts as no edge
inline constexpr double kEdgeSampleSpacingPx = 2.0;  // sampling along the projected edges

struct EdgeAlignment {
  double chamfer_px = 0.0;          // at the calibrated pose (see above)
  double chamfer_aligned_px = 0.0;  // at the aligned pose
  double seen_fraction = 0.0;       // share of the samples that project inside the image
  int samples = 0;
  double position_error_mm = 0.0;   // |camera centre moved| from the calibrated to the aligned pose
  double rotation_error_deg = 0.0;  // angle of the rotation between them
  cv::Matx44d T_world_camera_aligned = cv::Matx44d::eye();
};

// Canny edges of `colour` (BGR or grey 8-bit, the camera's image size) against `segments` seen
// by `camera`. Throws InputError naming `what` when the image size differs from the camera's.
EdgeAlignment measureEdgeAlignment(const cv::Mat& colour, const CameraModel& camera,
                                   const std::vector<EdgeSegment>& segments, const std::string& what);

// The colour image darkened, its Canny edges in blue, the segments projected through the
// calibrated pose in green and through the aligned pose in magenta (BGR 8-bit).
cv::Mat drawEdgeAlignment(const cv::Mat& colour, const CameraModel& camera,
                          const std::vector<EdgeSegment>& segments, const EdgeAlignment& alignment);

}  // namespace holo::calib
