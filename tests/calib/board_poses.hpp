// Board poses for synthetic calibration photos: a board in front of the camera, tilted, its
// centre at a chosen point of the camera frame.
#pragma once

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "holo/calib/board.hpp"

namespace holo::calib::test {

// Board -> camera transform: rotation by (tilt_x, tilt_y, roll) degrees, board centre at
// `centre_cam` (metres, camera frame).
inline cv::Matx44d boardPose(const BoardSpec& board, double tilt_x_deg, double tilt_y_deg, double roll_deg,
                             const cv::Vec3d& centre_cam) {
  const double d = CV_PI / 180.0;
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(tilt_x_deg * d, 0, 0), R);
  cv::Matx33d Ry, Rz;
  cv::Rodrigues(cv::Vec3d(0, tilt_y_deg * d, 0), Ry);
  cv::Rodrigues(cv::Vec3d(0, 0, roll_deg * d), Rz);
  R = R * Ry * Rz;
  const cv::Rect2d e = board.extent();
  const cv::Vec3d centre(e.x + e.width / 2, e.y + e.height / 2, 0);
  const cv::Vec3d t = centre_cam - R * centre;
  return {R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1],
          R(2, 0), R(2, 1), R(2, 2), t[2], 0,       0,       0,       1};
}

}  // namespace holo::calib::test
