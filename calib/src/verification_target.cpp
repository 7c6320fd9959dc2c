#include "holo/calib/verification_target.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/pose.hpp"

namespace holo::calib {

namespace {
constexpr double kDropBelowBaseTop = 0.08;
constexpr double kTurnDeg = 15.0;
constexpr double kLeanDeg = 10.0;
constexpr std::uint8_t kPlateGrey = 96, kWhite = 235, kBlack = 20;
}  // namespace

cv::Matx44d verificationTargetPose(int camera, double base_half_width) {
  const double azimuth = camera * CV_PI / 2;
  const cv::Vec3d out(std::sin(azimuth), 0, std::cos(azimuth));
  const cv::Vec3d z = out, y(0, -1, 0), x = y.cross(z);
  const cv::Matx33d upright(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]);
  cv::Matx33d lean, turn;
  cv::Rodrigues(cv::Vec3d(kLeanDeg * CV_PI / 180, 0, 0), lean);
  cv::Rodrigues(cv::Vec3d(0, kTurnDeg * CV_PI / 180, 0), turn);
  const cv::Matx33d R = upright * lean * turn;
  const cv::Vec3d centre =
      (base_half_width + kVerificationDistance) * out + cv::Vec3d(0, -kDropBelowBaseTop, 0);
  const double h = kVerificationPlateSize / 2;
  const cv::Vec3d t = centre - R * cv::Vec3d(h, h, 0);
  return {R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1],
          R(2, 0), R(2, 1), R(2, 2), t[2], 0,       0,       0,       1};
}

std::vector<EdgeSegment> verificationTargetEdges(const cv::Matx44d& T_world_target) {
  std::vector<EdgeSegment> edges;
  const double c = kVerificationPlateSize / 2;
  for (const double side : {kVerificationWhiteSquare, kVerificationBlackSquare}) {
    const double h = side / 2;
    const cv::Point3d corners[4] = {
        {c - h, c - h, 0}, {c + h, c - h, 0}, {c + h, c + h, 0}, {c - h, c + h, 0}};
    for (int k = 0; k < 4; ++k)
      edges.push_back(
          {transform(T_world_target, corners[k]), transform(T_world_target, corners[(k + 1) % 4])});
  }
  return edges;
}

BoardTexture renderVerificationTargetTexture(int pixels_per_metre) {
  const double s = pixels_per_metre;
  const int n = static_cast<int>(std::lround(kVerificationPlateSize * s));
  BoardTexture texture;
  texture.image = cv::Mat(n, n, CV_8UC1, cv::Scalar(kPlateGrey));
  const auto square = [&](double side, std::uint8_t level) {
    const int a = static_cast<int>(std::lround((kVerificationPlateSize - side) / 2 * s));
    const int b = static_cast<int>(std::lround((kVerificationPlateSize + side) / 2 * s));
    texture.image(cv::Rect(a, a, b - a, b - a)).setTo(level);
  };
  square(kVerificationWhiteSquare, kWhite);
  square(kVerificationBlackSquare, kBlack);
  // Pixel i covers metres [i, i + 1) / s: its centre, where warps sample it, is at (i + 0.5) / s.
  texture.board_to_pixel = cv::Matx33d(s, 0, -0.5, 0, s, -0.5, 0, 0, 1);
  return texture;
}

}  // namespace holo::calib
