// Rigid poses as OpenCV sees them (cv::Matx44d, row-major, double) and as the pipeline does
// (holo::mat4, GLM column-major float), with the error measures the calibration reports.
#pragma once

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "holo/core/math.hpp"

namespace holo::calib {

inline cv::Matx44d toMatx(const mat4& T) {
  cv::Matx44d out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = T[c][r];
  return out;
}

inline mat4 toMat4(const cv::Matx44d& T) {
  mat4 out(1.0f);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = static_cast<float>(T(r, c));
  return out;
}

// Rodrigues rotation vector (radians) and translation -> 4x4 rigid transform.
inline cv::Matx44d poseFromRt(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  return {R(0, 0), R(0, 1), R(0, 2), tvec[0], R(1, 0), R(1, 1), R(1, 2), tvec[1],
          R(2, 0), R(2, 1), R(2, 2), tvec[2], 0,       0,       0,       1};
}

inline void poseToRt(const cv::Matx44d& T, cv::Vec3d& rvec, cv::Vec3d& tvec) {
  cv::Rodrigues(cv::Matx33d(T.get_minor<3, 3>(0, 0)), rvec);
  tvec = {T(0, 3), T(1, 3), T(2, 3)};
}

inline cv::Matx44d rigidInverse(const cv::Matx44d& T) {
  const cv::Matx33d Rt = T.get_minor<3, 3>(0, 0).t();
  const cv::Vec3d t = -(Rt * cv::Vec3d(T(0, 3), T(1, 3), T(2, 3)));
  return {Rt(0, 0), Rt(0, 1), Rt(0, 2), t[0], Rt(1, 0), Rt(1, 1), Rt(1, 2), t[1],
          Rt(2, 0), Rt(2, 1), Rt(2, 2), t[2], 0,        0,        0,        1};
}

inline cv::Point3d transform(const cv::Matx44d& T, const cv::Point3d& p) {
  const cv::Vec4d q = T * cv::Vec4d(p.x, p.y, p.z, 1.0);
  return {q[0], q[1], q[2]};
}

// Distance between the translations (metres) and angle of the relative rotation (degrees).
inline double translationError(const cv::Matx44d& a, const cv::Matx44d& b) {
  return std::sqrt(std::pow(a(0, 3) - b(0, 3), 2) + std::pow(a(1, 3) - b(1, 3), 2) +
                   std::pow(a(2, 3) - b(2, 3), 2));
}
inline double rotationErrorDeg(const cv::Matx44d& a, const cv::Matx44d& b) {
  const cv::Matx33d R = a.get_minor<3, 3>(0, 0).t() * b.get_minor<3, 3>(0, 0);
  const double c = std::clamp((R(0, 0) + R(1, 1) + R(2, 2) - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / CV_PI;
}

}  // namespace holo::calib
