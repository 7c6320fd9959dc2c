#include "holo/calib/intrinsics.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "holo/core/error.hpp"

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

  cv::Mat K, dist, std_intrinsics, std_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  result.rms = cv::calibrateCamera(
      object_points, image_points, image_size, K, dist, rvecs, tvecs, std_intrinsics, std_extrinsics,
      per_view, 0, cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  for (int i = 0; i < per_view.rows; ++i) result.view_rms.push_back(per_view.at<double>(i));
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
