#include "holo/calib/intrinsics.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "holo/calib/quality.hpp"
#include "holo/core/error.hpp"
#include "holo/core/median.hpp"

namespace holo::calib {

IntrinsicsResult calibrateIntrinsics(const BoardSpec& board, const std::vector<BoardView>& views,
                                     cv::Size image_size, const std::string& source) {
  IntrinsicsResult result;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const BoardView& view : views) {
    if (!view.detection.usable()) {
      result.skipped_views.push_back(view.name);
      continue;
    }
    object_points.push_back(view.detection.object_points);
    image_points.push_back(view.detection.image_points);
    result.used_views.push_back(view.name);
  }
  if (static_cast<int>(object_points.size()) < kMinIntrinsicsViews)
    throw InputError(source, "board views",
                     "at least " + std::to_string(kMinIntrinsicsViews) + " images where the board (" +
                         board.describe() + ") is found",
                     std::to_string(object_points.size()) + " of " + std::to_string(views.size()));
  if (image_size.width <= 0 || image_size.height <= 0)
    throw InputError(source, "image size", "positive width and height");

  cv::Mat K, dist;
  const auto calibrate = [&] {
    cv::Mat std_intrinsics, std_extrinsics, per_view;
    std::vector<cv::Mat> rvecs, tvecs;
    result.rms = cv::calibrateCamera(
        object_points, image_points, image_size, K, dist, rvecs, tvecs, std_intrinsics, std_extrinsics,
        per_view, 0, cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
    result.view_rms.clear();
    for (int i = 0; i < per_view.rows; ++i) result.view_rms.push_back(per_view.at<double>(i));
  };
  calibrate();
  // Outliers: views far worse than the typical one (and worse than the step's threshold).
  const double limit = std::max(kIntrinsicsMaxRms, kIntrinsicsOutlierFactor * median(result.view_rms));
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < result.view_rms.size(); ++i)
    if (result.view_rms[i] <= limit) keep.push_back(i);
  if (keep.size() < result.view_rms.size() && static_cast<int>(keep.size()) >= kMinIntrinsicsViews) {
    std::vector<std::vector<cv::Point3f>> kept_object;
    std::vector<std::vector<cv::Point2f>> kept_image;
    std::vector<std::string> kept_names;
    for (std::size_t i = 0, k = 0; i < result.view_rms.size(); ++i) {
      if (k < keep.size() && keep[k] == i) {
        kept_object.push_back(object_points[i]);
        kept_image.push_back(image_points[i]);
        kept_names.push_back(result.used_views[i]);
        ++k;
      } else {
        result.outlier_views.push_back(result.used_views[i]);
        result.outlier_rms.push_back(result.view_rms[i]);
      }
    }
    object_points = std::move(kept_object);
    image_points = std::move(kept_image);
    result.used_views = std::move(kept_names);
    calibrate();
  }
  Intrinsics& out = result.intrinsics;
  out.width = image_size.width;
  out.height = image_size.height;
  out.fx = static_cast<float>(K.at<double>(0, 0));
  out.fy = static_cast<float>(K.at<double>(1, 1));
  out.cx = static_cast<float>(K.at<double>(0, 2));
  out.cy = static_cast<float>(K.at<double>(1, 2));
  for (int i = 0; i < 5 && i < static_cast<int>(dist.total()); ++i)
    out.distortion[static_cast<std::size_t>(i)] = static_cast<float>(dist.at<double>(i));
  if (!std::isfinite(result.rms) || !(out.fx > 0) || !(out.fy > 0))
    throw InputError(source, "calibration",
                     "a finite solution (views too similar or board too small in view?)");
  return result;
}

}  // namespace holo::calib
