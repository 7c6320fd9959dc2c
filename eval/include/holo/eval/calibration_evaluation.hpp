// How well a calibration of a recorded installation works end to end (`holopyramid eval
// calibration`): on a recording `holopyramid simulate --calibration` made (its truth under
// truth/calibration/), calibrates the recorded cameras (calib::runAutoCalibration on the
// recording's installation.yaml), compares every fitted figure with the truth, then runs the live
// loop headless on the recording's visitor frames three times: with the fitted calibration, with
// the true one, and with the fitted one less its depth registration and colour matching (depth
// scale and reprojection 1 / none, gains 1). The displayed images (each face view, 8-bit sRGB)
// of the first and third are compared with the true calibration's.
//
// Units: percent of the true value, millimetres, degrees, sRGB codes (0-255) per channel.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace holo::eval {

struct CalibrationEvalOptions {
  std::filesystem::path recording;  // made by `holopyramid simulate --calibration`
  std::filesystem::path out;        // calibration/, run_*.yaml, calibration_eval.json and .png
  int frames = 10;                  // visitor frames run through the loop (at most the recording's)
  int view_size = 160;              // face view pixels (square)
  int background_frames = 9;        // the recording's frames of the empty hall
  bool quiet = true;                // no progress bars
};

struct CameraCalibrationFigures {
  std::string serial;
  double intrinsics_error_pct = 0;  // worst of fx, fy, cx, cy against the truth
  double position_error_mm = 0;
  double rotation_error_deg = 0;
  double depth_scale_error_pct = 0;  // fitted metres per raw unit against the true one
  double gain_error_pct = 0;         // worst channel of the colour gains
};

struct DisplayedError {
  std::string run;         // "fitted", "without registration and colour matching"
  double mean_codes = 0;   // mean |difference| over every pixel and channel of every view and frame
  double relic_codes = 0;  // the same over the pixels the relic covers in the true run
  double max_codes = 0;    // the largest per-frame mean
};

struct CalibrationEvaluation {
  bool calibration_passed = false;  // every step passed and the calibration was saved
  std::vector<CameraCalibrationFigures> cameras;
  CameraCalibrationFigures worst;  // the worst of each figure over the cameras (serial "all")
  int frames = 0;                  // loop frames compared
  int view_size = 0;
  std::vector<DisplayedError> displayed;  // fitted, then without registration and colour matching
};

// Throws InputError naming the file when the recording lacks installation.yaml, scene.txt or
// truth/calibration (not made with --calibration). A calibration whose steps fail is reported
// (calibration_passed false) without the loop runs.
CalibrationEvaluation evaluateCalibration(const CalibrationEvalOptions& options, std::ostream& log);

std::string calibrationEvaluationJson(const CalibrationEvaluation& evaluation);

}  // namespace holo::eval
