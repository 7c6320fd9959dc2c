#include "holo/calib/quality.hpp"

#include <algorithm>
#include <cstdio>

namespace holo::calib {

namespace {
std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}
}  // namespace

std::string formatVerdict(const StepVerdict& v) {
  std::string line = v.step + ": " + v.figure + " " + number(v.value) + " (" +
                     (v.figure.find("correlation") != std::string::npos ? ">= " : "< ") +
                     number(v.threshold) + ") " + (v.pass ? "PASS" : "FAIL");
  if (!v.pass && !v.hint.empty()) line += "\n  hint: " + v.hint;
  return line;
}

StepVerdict judgeIntrinsics(const std::string& step, double rms, int views, int offered,
                            double board_fraction) {
  StepVerdict v{step, "RMS reprojection error (px)", rms, kIntrinsicsMaxRms, false, {}};
  if (views < kIntrinsicsMinViews)
    v.hint = "too few views: " + std::to_string(views) + " different views of the board held still, in " +
             std::to_string(offered) + " frames; take at least " + std::to_string(kIntrinsicsMinViews) +
             ", tilting the board and moving it into every corner of the picture";
  else if (rms >= kIntrinsicsWrongBoardRms)
    v.hint = "the corners fit no camera (error of " + number(rms) +
             " px): check that the board given is the one printed (squares across and down, marker size, "
             "dictionary)";
  else if (rms >= kIntrinsicsMaxRms && board_fraction < 0.25)
    v.hint = "board too far: it covers only " + number(100 * board_fraction) +
             "% of the picture width; bring it closer so it fills about half";
  else if (rms >= kIntrinsicsMaxRms)
    v.hint = "corners are imprecise: hold the board still (motion blur), light it evenly, keep it flat";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeExtrinsics(const std::string& step, double rms, int corners, double board_fraction) {
  StepVerdict v{step, "RMS reprojection error (px)", rms, kExtrinsicsMaxRms, false, {}};
  if (corners < kExtrinsicsMinCorners)
    v.hint = "the camera sees too little of the board (" + std::to_string(corners) +
             " corners): check the board lies on its marked spot and nothing covers it";
  else if (rms >= kExtrinsicsMaxRms && board_fraction < 0.15)
    v.hint = "board too far from the camera: use the nearer marked spot or a larger board";
  else if (rms >= kExtrinsicsMaxRms)
    v.hint =
        "the board's corners do not fit one pose: it may have moved (motion blur), be bent, or the "
        "camera's intrinsics may be wrong; recalibrate intrinsics first";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeLoopClosure(const std::string& step, double translation_mm, double rotation_deg) {
  StepVerdict v{step, "relative pose disagreement (mm)", translation_mm, kLoopClosureMaxMm, false, {}};
  if (translation_mm >= kLoopClosureMaxMm || rotation_deg >= kLoopClosureMaxDeg)
    v.hint = "the two cameras' poses disagree with the board they both saw (" + number(translation_mm) +
             " mm, " + number(rotation_deg) +
             " degrees): check that each board stood exactly on its marked spot and that no camera moved "
             "during the step, then measure it again";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeBackground(const std::string& step, double invalid_fraction, double colour_mad) {
  StepVerdict v{step, "invalid depth fraction", invalid_fraction, kBackgroundMaxInvalid, false, {}};
  if (invalid_fraction >= kBackgroundMaxInvalid)
    v.hint =
        "too much missing depth: check that the lens is not covered or in direct sunlight and that the "
        "camera "
        "looks at the room, not the ceiling; remove shiny or black objects near it";
  else if (colour_mad >= kBackgroundMaxColourMad)
    v.hint = "the scene changed while capturing (colour varies by " + number(colour_mad) +
             " levels): make sure nobody walks in front of the cameras and the lights are steady";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgePanorama(const std::string& step, double correlation) {
  StepVerdict v{step, "normalised correlation with the panorama", correlation, kPanoramaMinCorrelation, false,
                {}};
  if (correlation < kPanoramaMinCorrelation)
    v.hint =
        "the camera's view does not match the panorama: was the panorama taken in this hall, with the "
        "same furniture? Retake it from the pyramid's position";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeDisplay(const std::string& step, double residual_px) {
  StepVerdict v{step, "test pattern residual (px)", residual_px, kDisplayMaxResidualPx, false, {}};
  if (residual_px >= kDisplayMaxResidualPx)
    v.hint =
        "the face's picture is distorted, not just shifted or turned: check the monitor's own scaling "
        "(set it to native resolution, no overscan)";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeDepthRegistration(const std::string& step, double rms_distance_mm, int views) {
  StepVerdict v{step,
                "board plane distance, depth against colour (RMS mm)",
                rms_distance_mm,
                kDepthRegistrationMaxRmsMm,
                false,
                {}};
  if (views < kDepthRegistrationMinViews)
    v.hint = "the board was found in depth in only " + std::to_string(views) +
             " views: hold it flat and uncovered, 30-60 cm away, tilted both ways";
  else if (!(rms_distance_mm < kDepthRegistrationMaxRmsMm))
    v.hint = "the board's depth disagrees with its corners by " + number(rms_distance_mm) +
             " mm: is the board bent, or the depth camera's picture from another instant (hold it still)?";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeColourGains(const std::string& step, vec3 gains) {
  double worst = 1.0;
  for (int c = 0; c < 3; ++c) {
    const double g = gains[c];
    worst = std::max(worst, g > 0 ? std::max(g, 1.0 / g) : 1e9);
  }
  StepVerdict v{step, "largest colour correction (factor)", worst, kColourMaxCorrection, false, {}};
  if (!(worst < kColourMaxCorrection))
    v.hint = "this camera's colours are " + number(worst) +
             " times off the others': set its white balance and exposure like theirs, then calibrate again";
  v.pass = v.hint.empty();
  return v;
}

StepVerdict judgeVerification(const std::string& step, const EdgeAlignment& a) {
  StepVerdict v{step, "pose error from the jig's edges (mm)", a.position_error_mm, kVerificationMaxMm, false,
                {}};
  if (a.seen_fraction < kVerificationMinSeen)
    v.hint = "the camera sees only " + number(100 * a.seen_fraction) +
             "% of the verification jig where its calibration puts it: check that the jig is mounted on "
             "this side of the base; if it is, the camera's pose is far off: measure the poses again";
  else if (!(a.chamfer_aligned_px < kVerificationMaxEdgePx))
    v.hint = "the jig's printed squares are not found where the calibration puts them (" +
             number(a.chamfer_aligned_px) +
             " px from the nearest edges): check that the jig is mounted and lit and nothing covers it; "
             "if it is, the camera's pose or intrinsics are far off: calibrate again";
  else if (!(a.position_error_mm < kVerificationMaxMm) || !(a.rotation_error_deg < kVerificationMaxDeg))
    v.hint = "the camera's calibrated pose is off by " + number(a.position_error_mm) + " mm and " +
             number(a.rotation_error_deg) +
             " degrees: was the camera knocked since the poses were measured? Tighten its mount and "
             "measure the poses again";
  v.pass = v.hint.empty();
  return v;
}

}  // namespace holo::calib
