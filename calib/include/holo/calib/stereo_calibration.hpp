// A stereo pair calibrated from two folders of photos (photo k of the left set taken at the same
// moment as photo k of the right set): each camera's intrinsics through the intrinsics step the
// live cameras run (PhotoSource folders in a CaptureRig, CalibrationSession), then the pair's
// relative pose from the photo pairs in which both cameras saw the board (one joint
// Levenberg-Marquardt adjustment, relativePoseFromSharedViews), with its loop closure (each pair
// on its own against the joint estimate), cross-checked by cv::stereoCalibrate with the
// intrinsics fixed, and the rectification it implies (cv::stereoRectify): corresponding corners
// must land on the same row.
//
// Units: metres for poses, millimetres and degrees in the figures named so, pixels for errors.
// Frames: T_left_right maps right-camera coordinates to left-camera coordinates; R and T follow
// cv::stereoCalibrate (x_right = R x_left + T).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/extrinsics.hpp"
#include "holo/calib/quality.hpp"

namespace holo::calib {

struct StereoCalibration {
  std::string board;  // the board's description
  cv::Size image_size;
  CameraCalibration left, right;      // intrinsics and their RMS; serials "left" and "right"
  std::vector<StepVerdict> verdicts;  // the intrinsics step's, one per camera
  std::vector<std::string> left_files, right_files;
  std::vector<int> shared;  // indices of the photo pairs in which both cameras saw the board
  RelativePose pose;        // T_a_b = T_left_right; rms_px over both cameras; per-pair loop closure
  double baseline_mm = 0.0;
  double rotation_deg = 0.0;
  double loop_median_mm = 0.0, loop_worst_mm = 0.0, loop_median_deg = 0.0, loop_worst_deg = 0.0;
  // cv::stereoCalibrate (CALIB_FIX_INTRINSIC) on the same corners: its RMS and how far its pose
  // is from the joint estimate.
  double opencv_rms_px = 0.0;
  double opencv_difference_mm = 0.0, opencv_difference_deg = 0.0;
  // After cv::stereoRectify: |row_left - row_right| of corresponding corners, over every shared pair.
  double rectified_row_median_px = 0.0, rectified_row_worst_px = 0.0;
  cv::Matx33d R, R1, R2;
  cv::Vec3d T;
  cv::Matx34d P1, P2;
  cv::Matx44d Q;
  // The first shared pair rectified side by side, every 24th row drawn as an epipolar line, the
  // corners on the rectified images (BGR 8-bit).
  cv::Mat picture;
};

// Throws InputError naming the pattern or file and what was expected when a pattern matches no
// file, the two sets differ in count or image size, a camera finds the board in fewer than
// kIntrinsicsMinViews photos, or no pair has the board in both. The intrinsics verdicts are
// reported, not thrown: a failing one still gives a result (the caller decides).
StereoCalibration calibrateStereoPhotos(const std::string& left_pattern, const std::string& right_pattern,
                                        const BoardSpec& board, std::ostream& log, bool quiet = true);

// OpenCV FileStorage YAML (stock cv::FileStorage reads it), written atomically: image size, each
// camera's camera_matrix and distortion_coefficients, R, T (metres), T_left_right, the
// rectification (R1, R2, P1, P2, Q), and the figures above.
void saveStereoCalibration(const std::filesystem::path& file, const StereoCalibration& stereo);

}  // namespace holo::calib
