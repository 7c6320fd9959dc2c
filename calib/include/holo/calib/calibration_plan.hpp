// What one run of every calibration step takes and gives: the boards the appliance ships with,
// where the placement board stands in front of each camera, the run's settings, and its report
// (each step's verdict, the cameras' and the pyramid's calibration, whether it was saved).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/quality.hpp"
#include "holo/core/math.hpp"

namespace holo::calib {

// The boards the appliance ships with (BoardSpec::parse text): a hand-held one for intrinsics
// (50 mm squares keep ChArUco's refinement gap wide enough on the wide cameras, docs/calib.md)
// and a larger one for the easel at the marked placements.
inline constexpr const char* kDefaultIntrinsicsBoard = "charuco:7x5:0.05:0.03:DICT_5X5_100";
inline constexpr const char* kDefaultPlacementBoard = "charuco:7x5:0.08:0.06:DICT_5X5_100";

struct AutoCalibrationConfig {
  BoardSpec intrinsics_board;
  BoardSpec placement_board;
  std::vector<cv::Matx44d> placements;  // T_world_board of the board in front of each camera
  int background_frames = 9;
  cv::Size face_view{960, 540};
  vec3 panorama_position{0.0f, 0.35f, 0.0f};
  // The most frames a step takes from one camera before it gives up (live cameras: 100 s at
  // 30 fps); a step also ends when the technician takes the board away or the frames end.
  int max_frames_per_step = 3000;
};

// The marked easel spots: the placement board upright 0.75 m in front of each face of a base
// `base_half_width` wide, turned 20 degrees and leaned back 12 degrees (a well-conditioned pose).
std::vector<cv::Matx44d> defaultBoardPlacements(const BoardSpec& board, int cameras,
                                                double base_half_width = 0.3);

struct AutoCalibrationReport {
  std::vector<StepVerdict> verdicts;
  std::vector<CameraCalibration> cameras;
  PyramidCalibration pyramid;
  bool saved = false;
  bool allPassed() const;
};

}  // namespace holo::calib
