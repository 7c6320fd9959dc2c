// Each camera's pose in the pyramid frame (T_world_camera) from ChArUco boards.
//
// A board placement is where a board lies in the world frame (T_world_board, metres). Known
// placements come from the configuration (the technician lays the board at marked spots around
// the base); unknown placements are boards held where two cameras see them at once. Every camera
// first gets its pose from the boards at known placements it sees (solvePnP on all their corners,
// refined by Levenberg-Marquardt); then one joint Levenberg-Marquardt adjustment over all camera
// poses and all unknown board poses minimises every corner's reprojection error, so a board two
// cameras see at once ties their poses together.
#pragma once

#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::calib {

struct BoardPlacement {
  cv::Matx44d T_world_board = cv::Matx44d::eye();  // used as is when known, else estimated
  bool known = true;
};

// One camera's detection of the board at one placement.
struct BoardObservation {
  int camera = 0;
  int placement = 0;
  BoardDetection detection;
};

struct ExtrinsicsProblem {
  std::vector<Intrinsics> cameras;
  std::vector<BoardPlacement> placements;
  std::vector<BoardObservation> observations;
  bool joint_refinement = true;
};

struct ExtrinsicsResult {
  std::vector<cv::Matx44d> T_world_camera;  // per camera
  std::vector<double> camera_rms;           // per camera: RMS reprojection error, pixels
  std::vector<int> camera_corners;          // per camera: corners used
  std::vector<cv::Matx44d> T_world_board;   // per placement (known ones unchanged)
  double rms = 0.0;                         // over all corners, pixels
  int iterations = 0;                       // of the joint adjustment (0 when not run)
};

// Throws InputError (naming `source`) when a camera sees no board at a known placement (with
// at least 6 corners), or an observation names a camera or placement that does not exist.
ExtrinsicsResult calibrateExtrinsics(const ExtrinsicsProblem& problem,
                                     const std::string& source = "extrinsics");

// Two cameras' relative pose from views in which both saw the same board at the same moment (a
// stereo pair, or two neighbouring cameras): camera a's frame is the world, the first pair's
// board is placed by camera a's solvePnP and every other pair's board is estimated, in one joint
// adjustment (calibrateExtrinsics). The loop closure: each pair on its own gives a relative pose
// (T_a_board * T_b_board^-1); their disagreement with the joint estimate is reported.
struct SharedBoardView {
  BoardDetection a;
  BoardDetection b;
};
struct RelativePose {
  cv::Matx44d T_a_b = cv::Matx44d::eye();  // camera b -> camera a, metres
  int pairs = 0;
  double rms_px = 0.0;                      // joint reprojection error over both cameras
  std::vector<double> pair_translation_mm;  // per pair: its own relative pose against T_a_b
  std::vector<double> pair_rotation_deg;
};
// Throws InputError (naming `source`) with no pair in which both detections are usable.
RelativePose relativePoseFromSharedViews(const Intrinsics& a, const Intrinsics& b,
                                         const std::vector<SharedBoardView>& views,
                                         const std::string& source = "shared views");

}  // namespace holo::calib
