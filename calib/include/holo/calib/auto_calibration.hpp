// Every calibration step in order, without a window (`holopyramid calibrate --auto`, scripts and
// tests): intrinsics from board photos, each camera's pose from boards at known placements,
// background capture, panorama yaw, display alignment; each step prints its quality figure and a
// pass/fail verdict with a hint, and the results are saved atomically (camera_SERIAL.yml per
// camera, pyramid.yml, background PNGs and detection pictures) into one folder.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/calibration_rig.hpp"
#include "holo/calib/quality.hpp"
#include "holo/core/rgbd_frame.hpp"

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

// Runs the steps, a line per step (and hints) to `log`; saves into `out_dir` only when every
// step passed. Otherwise nothing is written (the previous calibration stays in force) and the
// report says why: a step that could not be measured at all rethrows its InputError.
AutoCalibrationReport runAutoCalibration(CalibrationRig& rig, const AutoCalibrationConfig& config,
                                         const std::filesystem::path& out_dir, std::ostream& log,
                                         bool quiet = false);

}  // namespace holo::calib
