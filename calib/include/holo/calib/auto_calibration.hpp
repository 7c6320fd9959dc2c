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
#include "holo/calib/quality.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::calib {

// What the steps need from the appliance: photos and frames from each camera, the panorama and
// where the technician saw the test pattern's dots on each face. Real cameras and the simulated
// museum both provide it.
class CalibrationRig {
 public:
  virtual ~CalibrationRig() = default;
  virtual int cameraCount() const = 0;
  virtual std::string serial(int camera) const = 0;
  virtual cv::Size imageSize(int camera) const = 0;
  virtual int intrinsicsViewCount() const = 0;
  // Colour photo `view` of the intrinsics board held in front of `camera`.
  virtual cv::Mat intrinsicsPhoto(int camera, int view) const = 0;
  // Colour photo of the extrinsics board standing at the placement in front of `camera`.
  virtual cv::Mat placementPhoto(int camera) const = 0;
  // Frame `index` of the empty hall.
  virtual RgbdFrame backgroundFrame(int camera, int index) const = 0;
  virtual cv::Mat panorama() const = 0;  // CV_32FC3 linear BGR, equirectangular
  // Where each dot of testPatternDots(view) appeared on face `face` (screen pixels).
  virtual std::vector<cv::Point2f> observedTestPattern(int face, cv::Size view) const = 0;
};

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
};

// The marked easel spots: the placement board upright 0.75 m in front of each face of a base
// `base_half_width` wide, turned 20 degrees and leaned back 12 degrees (a well-conditioned pose).
std::vector<cv::Matx44d> defaultBoardPlacements(const BoardSpec& board, int cameras,
                                                double base_half_width = 0.3);

struct AutoCalibrationReport {
  std::vector<StepVerdict> verdicts;
  std::vector<CameraCalibration> cameras;
  PyramidCalibration pyramid;
  bool allPassed() const;
};

// Runs the steps, writing into `out_dir` and a line per step (and hints) to `log`.
AutoCalibrationReport runAutoCalibration(const CalibrationRig& rig, const AutoCalibrationConfig& config,
                                         const std::filesystem::path& out_dir, std::ostream& log,
                                         bool quiet = false);

}  // namespace holo::calib
