// Depth-to-colour registration of a camera whose colour and depth come from two devices, and
// the depth device's true scale, from the calibration board: in each view the board's plane is
// known in the colour camera's frame (its pose from the detected corners) and measured in the
// depth camera's frame (a plane fitted to the depth pixels on the board). With planes
// n_c . X = d_c (colour frame) and n_d . X = d_d (depth frame, nominal metres) of the same board:
//   n_c = R n_d                      (rotation: the normals of >= 3 differently tilted views)
//   n_c . t + s d_d = d_c            (translation t and scale factor s: linear, >= 4 views)
// where X_colour = R X_depth + t and true depth = s x nominal depth. The fitted metres per raw
// unit is s x the nominal one.
//
// Units: metres, radians unless named; planes' normals point away from their camera (d > 0).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::calib {

// n . X = distance, n unit, distance > 0 (the camera's centre is on the plane's negative side).
struct Plane {
  cv::Vec3d normal{0, 0, 1};
  double distance = 0.0;
};

// The board's plane in the colour camera's frame, from its detected corners (solvePnP with the
// colour intrinsics). nullopt when the detection has fewer than 6 corners.
std::optional<Plane> boardPlaneInCamera(const BoardDetection& detection, const Intrinsics& colour);

// The board's pose (board -> colour camera) from its detected corners; nullopt as above.
std::optional<cv::Matx44d> boardPoseInCamera(const BoardDetection& detection, const Intrinsics& colour);

struct DepthPlaneFit {
  Plane plane;
  int inliers = 0;     // depth pixels within 1 cm of the plane
  double rms_m = 0.0;  // their RMS distance to it
};

// Fits the board's plane in a depth image (CV_32FC1 nominal metres, 0 = invalid, seen through
// `depth` intrinsics): the board's printed extent, shrunk by `inset` (a share of each side, so
// that a rough `T_depth_colour` guess still lands on the board), is projected from the colour
// frame where `T_colour_board` puts it into the depth image; the valid pixels inside are
// back-projected, a RANSAC plane (deterministic seed) found and refitted by least squares on its
// inliers. nullopt with fewer than 200 inliers.
std::optional<DepthPlaneFit> fitBoardPlaneInDepth(const cv::Mat& depth, const Intrinsics& depth_intrinsics,
                                                  const BoardSpec& board, const cv::Matx44d& T_colour_board,
                                                  const cv::Matx44d& T_depth_colour_guess,
                                                  double inset = 0.2);

struct PlanePair {
  Plane colour;  // the board in the colour camera's frame
  Plane depth;   // the same board in the depth camera's frame, nominal metres
};

struct DepthRegistration {
  cv::Matx44d T_colour_depth = cv::Matx44d::eye();  // depth camera -> colour camera, metres
  double scale_factor = 1.0;                        // true depth / nominal depth
  double rms_distance_mm = 0.0;                     // plane distance residual over the views
  double rms_normal_deg = 0.0;                      // normal residual over the views
  int views = 0;
};

// The registration from >= 4 views whose normals span 3D (the board tilted differently); throws
// InputError (naming `source`, with a hint) with fewer views or normals too alike to fix the
// rotation or the translation.
DepthRegistration fitDepthRegistration(const std::vector<PlanePair>& views, const std::string& source);

}  // namespace holo::calib
