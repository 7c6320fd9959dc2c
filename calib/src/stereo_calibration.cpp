#include "holo/calib/stereo_calibration.hpp"

#include <algorithm>
#include <array>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/board_tracking.hpp"
#include "holo/calib/calibration_session.hpp"
#include "holo/calib/capture_rig.hpp"
#include "holo/calib/pose.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/median.hpp"

namespace holo::calib {
namespace {

cv::Matx33d cameraMatrix(const Intrinsics& K) {
  return {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
}

cv::Mat distortion(const Intrinsics& K) {
  cv::Mat d(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) d.at<double>(0, i) = K.distortion[static_cast<std::size_t>(i)];
  return d;
}

// The corners both detections hold (same board-frame point), in the same order.
void commonCorners(const BoardDetection& a, const BoardDetection& b, std::vector<cv::Point3f>& object,
                   std::vector<cv::Point2f>& in_a, std::vector<cv::Point2f>& in_b) {
  for (std::size_t i = 0; i < a.object_points.size(); ++i) {
    const auto it = std::find(b.object_points.begin(), b.object_points.end(), a.object_points[i]);
    if (it == b.object_points.end()) continue;
    object.push_back(a.object_points[i]);
    in_a.push_back(a.image_points[i]);
    in_b.push_back(b.image_points[static_cast<std::size_t>(it - b.object_points.begin())]);
  }
}

std::string fileName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

}  // namespace

StereoCalibration calibrateStereoPhotos(const std::string& left_pattern, const std::string& right_pattern,
                                        const BoardSpec& board, std::ostream& log, bool quiet) {
  StereoCalibration out;
  out.board = board.describe();
  out.left_files = PhotoSource::expand(left_pattern);
  out.right_files = PhotoSource::expand(right_pattern);
  const std::size_t n = out.left_files.size();
  if (out.right_files.size() != n)
    throw InputError(right_pattern, "photos",
                     std::to_string(n) + " photos like " + left_pattern + " (paired by their sorted order)",
                     std::to_string(out.right_files.size()));

  std::vector<std::unique_ptr<capture::CameraSource>> sources;
  sources.push_back(std::make_unique<PhotoSource>("left", out.left_files));
  sources.push_back(std::make_unique<PhotoSource>("right", out.right_files));
  CaptureRig rig(std::move(sources), cv::Mat(), {}, "stereo photos " + left_pattern + " and " + right_pattern,
                 /*stills=*/true);
  out.image_size = rig.imageSize(0);
  if (rig.imageSize(1) != out.image_size)
    throw InputError(out.right_files.front(), "image size",
                     std::to_string(out.image_size.width) + "x" + std::to_string(out.image_size.height) +
                         " like " + out.left_files.front() + " (one rectified pair)",
                     std::to_string(rig.imageSize(1).width) + "x" + std::to_string(rig.imageSize(1).height));

  AutoCalibrationConfig config;
  config.intrinsics_board = board;
  config.placement_board = board;
  config.placements = defaultBoardPlacements(board, 2);
  CalibrationSession session(rig, config);
  const StepOutcome& outcome = session.measure(CalibrationStep::Intrinsics, log, quiet);
  const std::array<const std::vector<BoardFrameObservation>*, 2> observations = {
      &session.boardObservations(CalibrationStep::Intrinsics, 0),
      &session.boardObservations(CalibrationStep::Intrinsics, 1)};
  const std::array<const std::string*, 2> patterns = {&left_pattern, &right_pattern};
  for (std::size_t c = 0; c < 2; ++c) {
    const auto seen = std::count_if(observations[c]->begin(), observations[c]->end(),
                                    [](const BoardFrameObservation& o) { return o.detection.usable(); });
    if (seen < kIntrinsicsMinViews)
      throw InputError(*patterns[c], "board",
                       "at least " + std::to_string(kIntrinsicsMinViews) + " photos showing the " + out.board,
                       "found in " + std::to_string(seen) + " of " + std::to_string(n) + " photos");
  }
  if (!outcome.error.empty())
    throw InputError(left_pattern + ", " + right_pattern, "intrinsics", outcome.error);
  // Colour gains matter for cameras whose pictures are blended, not for a stereo pair's geometry.
  for (const StepVerdict& verdict : outcome.verdicts)
    if (verdict.step.rfind("intrinsics", 0) == 0) out.verdicts.push_back(verdict);
  const AutoCalibrationReport report = session.report();
  out.left = report.cameras[0];
  out.right = report.cameras[1];

  // Photo k of each set was taken at the same moment. The step looks at the photos in order and
  // stops once it has its views and the board has been missing from 3 photos in a row (a live
  // camera's "board taken away"): pairs after that are not looked at, and are named.
  std::vector<SharedBoardView> views;
  const std::size_t looked = std::min(observations[0]->size(), observations[1]->size());
  if (looked < n)
    log << "  pairs from " << fileName(out.left_files[looked]) << " / " << fileName(out.right_files[looked])
        << " on not looked at: the step stopped after 3 photos without the board\n";
  for (std::size_t k = 0; k < looked; ++k) {
    const BoardDetection& a = (*observations[0])[k].detection;
    const BoardDetection& b = (*observations[1])[k].detection;
    if (a.usable() && b.usable()) {
      out.shared.push_back(static_cast<int>(k));
      views.push_back({a, b});
    } else {
      log << "  pair " << fileName(out.left_files[k]) << " / " << fileName(out.right_files[k])
          << ": board not found in "
          << (a.usable() ? fileName(out.right_files[k]) : fileName(out.left_files[k])) << ", pair left out\n";
    }
  }
  if (views.empty())
    throw InputError(left_pattern + ", " + right_pattern, "photo pairs",
                     "at least one pair (left k, right k) in which both show the " + out.board, "none");
  out.pose = relativePoseFromSharedViews(out.left.intrinsics, out.right.intrinsics, views,
                                         left_pattern + ", " + right_pattern);
  cv::Vec3d rvec, tvec;
  poseToRt(out.pose.T_a_b, rvec, tvec);
  out.baseline_mm = 1000.0 * cv::norm(tvec);
  out.rotation_deg = cv::norm(rvec) * 180.0 / CV_PI;
  out.loop_median_mm = median(out.pose.pair_translation_mm);
  out.loop_worst_mm =
      *std::max_element(out.pose.pair_translation_mm.begin(), out.pose.pair_translation_mm.end());
  out.loop_median_deg = median(out.pose.pair_rotation_deg);
  out.loop_worst_deg =
      *std::max_element(out.pose.pair_rotation_deg.begin(), out.pose.pair_rotation_deg.end());

  const cv::Matx44d T_right_left = rigidInverse(out.pose.T_a_b);
  out.R = T_right_left.get_minor<3, 3>(0, 0);
  out.T = {T_right_left(0, 3), T_right_left(1, 3), T_right_left(2, 3)};

  const cv::Matx33d K1 = cameraMatrix(out.left.intrinsics), K2 = cameraMatrix(out.right.intrinsics);
  const cv::Mat D1 = distortion(out.left.intrinsics), D2 = distortion(out.right.intrinsics);
  // The pairs with enough corners in common (a ChArUco board may be partly hidden in one camera).
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> left_points, right_points;
  std::vector<std::size_t> used;  // their photo indices
  for (std::size_t i = 0; i < views.size(); ++i) {
    std::vector<cv::Point3f> o;
    std::vector<cv::Point2f> a, b;
    commonCorners(views[i].a, views[i].b, o, a, b);
    if (o.size() < 6) continue;
    object.push_back(std::move(o));
    left_points.push_back(std::move(a));
    right_points.push_back(std::move(b));
    used.push_back(static_cast<std::size_t>(out.shared[i]));
  }
  if (used.empty())
    throw InputError(left_pattern + ", " + right_pattern, "photo pairs",
                     "a pair in which both cameras see at least 6 of the same corners", "none");

  {  // An independent estimate of the same pose: OpenCV's own stereo calibration.
    cv::Mat K1c(K1), K2c(K2), D1c = D1.clone(), D2c = D2.clone(), R_cv, T_cv, E, F;
    out.opencv_rms_px = cv::stereoCalibrate(object, left_points, right_points, K1c, D1c, K2c, D2c,
                                            out.image_size, R_cv, T_cv, E, F, cv::CALIB_FIX_INTRINSIC);
    cv::Matx44d T_cv_right_left = cv::Matx44d::eye();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) T_cv_right_left(r, c) = R_cv.at<double>(r, c);
      T_cv_right_left(r, 3) = T_cv.at<double>(r, 0);
    }
    out.opencv_difference_mm = 1000.0 * translationError(T_cv_right_left, T_right_left);
    out.opencv_difference_deg = rotationErrorDeg(T_cv_right_left, T_right_left);
  }

  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K1, D1, K2, D2, out.image_size, cv::Mat(out.R), cv::Mat(out.T), R1, R2, P1, P2, Q,
                    cv::CALIB_ZERO_DISPARITY, 0.0);
  out.R1 = cv::Matx33d(R1);
  out.R2 = cv::Matx33d(R2);
  out.P1 = cv::Matx34d(P1);
  out.P2 = cv::Matx34d(P2);
  out.Q = cv::Matx44d(Q);
  std::vector<double> row_errors;
  std::vector<std::vector<cv::Point2f>> rect_left(used.size()), rect_right(used.size());
  for (std::size_t i = 0; i < used.size(); ++i) {
    cv::undistortPoints(left_points[i], rect_left[i], K1, D1, R1, P1);
    cv::undistortPoints(right_points[i], rect_right[i], K2, D2, R2, P2);
    for (std::size_t j = 0; j < rect_left[i].size(); ++j)
      row_errors.push_back(std::abs(rect_left[i][j].y - rect_right[i][j].y));
  }
  out.rectified_row_median_px = median(row_errors);
  out.rectified_row_worst_px = *std::max_element(row_errors.begin(), row_errors.end());

  const std::size_t k = used.front();
  std::array<cv::Mat, 2> rectified;
  for (std::size_t c = 0; c < 2; ++c) {
    const cv::Mat photo = cv::imread(c == 0 ? out.left_files[k] : out.right_files[k], cv::IMREAD_COLOR);
    cv::Mat map1, map2;
    cv::initUndistortRectifyMap(c == 0 ? K1 : K2, c == 0 ? D1 : D2, c == 0 ? R1 : R2, c == 0 ? P1 : P2,
                                out.image_size, CV_32FC1, map1, map2);
    cv::remap(photo, rectified[c], map1, map2, cv::INTER_LINEAR);
    for (const cv::Point2f& p : c == 0 ? rect_left.front() : rect_right.front())
      cv::circle(rectified[c], p, 3, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  }
  cv::hconcat(rectified[0], rectified[1], out.picture);
  for (int y = 12; y < out.picture.rows; y += 24)
    cv::line(out.picture, {0, y}, {out.picture.cols - 1, y}, cv::Scalar(0, 200, 0), 1);
  return out;
}

void saveStereoCalibration(const std::filesystem::path& file, const StereoCalibration& s) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << "image_width" << s.image_size.width << "image_height" << s.image_size.height << "board" << s.board;
  fs << "left_camera_matrix" << cv::Mat(cameraMatrix(s.left.intrinsics)) << "left_distortion_coefficients"
     << distortion(s.left.intrinsics) << "left_rms" << s.left.rms;
  fs << "right_camera_matrix" << cv::Mat(cameraMatrix(s.right.intrinsics)) << "right_distortion_coefficients"
     << distortion(s.right.intrinsics) << "right_rms" << s.right.rms;
  fs << "R" << cv::Mat(s.R) << "T" << cv::Mat(s.T) << "T_left_right" << cv::Mat(s.pose.T_a_b);
  fs << "R1" << cv::Mat(s.R1) << "R2" << cv::Mat(s.R2) << "P1" << cv::Mat(s.P1) << "P2" << cv::Mat(s.P2)
     << "Q" << cv::Mat(s.Q);
  fs << "pairs" << s.pose.pairs << "rms" << s.pose.rms_px << "baseline_mm" << s.baseline_mm << "rotation_deg"
     << s.rotation_deg;
  fs << "loop_closure_median_mm" << s.loop_median_mm << "loop_closure_worst_mm" << s.loop_worst_mm
     << "loop_closure_median_deg" << s.loop_median_deg << "loop_closure_worst_deg" << s.loop_worst_deg;
  fs << "opencv_stereo_rms" << s.opencv_rms_px << "opencv_stereo_difference_mm" << s.opencv_difference_mm
     << "opencv_stereo_difference_deg" << s.opencv_difference_deg;
  fs << "rectified_row_error_median_px" << s.rectified_row_median_px << "rectified_row_error_worst_px"
     << s.rectified_row_worst_px << "date" << utcTimestamp();
  writeFileAtomically(file, fs.releaseAndGetString());
}

}  // namespace holo::calib
