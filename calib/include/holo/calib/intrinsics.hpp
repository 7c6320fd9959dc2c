// Camera intrinsics from photos of a chessboard or ChArUco board (OpenCV calibrateCamera, the
// five-parameter plumb-bob model). The quality figure is the RMS reprojection error in pixels.
// A view whose own RMS error is an outlier (above kIntrinsicsMaxRms and 3 times the median view's,
// quality.hpp) is dropped and the camera calibrated again without it: one blurred or mis-detected
// view must not spoil the others.
#pragma once

#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::calib {

// One photo's detection, remembered with the photo's name for reports.
struct BoardView {
  std::string name;
  BoardDetection detection;
};

struct IntrinsicsResult {
  Intrinsics intrinsics;
  double rms = 0.0;              // RMS reprojection error over all corners, pixels
  std::vector<double> view_rms;  // per used view, pixels (same order as used_views)
  std::vector<std::string> used_views;
  std::vector<std::string> skipped_views;  // no board found or too few corners
  std::vector<std::string> outlier_views;  // dropped: their RMS error was an outlier
  std::vector<double> outlier_rms;         // their RMS error in the first calibration, pixels
};

inline constexpr int kMinIntrinsicsViews = 3;

// Calibrates from views of `image_size`. Views whose detection is not usable are skipped (and
// listed). Throws InputError (naming `source`) with fewer than kMinIntrinsicsViews usable views.
IntrinsicsResult calibrateIntrinsics(const BoardSpec& board, const std::vector<BoardView>& views,
                                     cv::Size image_size, const std::string& source = "images");

}  // namespace holo::calib
