#include "holo/calib/panorama_alignment.hpp"

#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::calib {

namespace {

struct Sample {
  vec3 direction;  // world
  double value;    // log luminance of the camera pixel
};

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double correlation(const cv::Mat& panorama, const std::vector<Sample>& samples, float yaw) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (const Sample& s : samples) {
    const double a = std::log(1e-4 + std::max(0.0f, luminance(equirect::sample(panorama, s.direction, yaw))));
    const double b = s.value;
    sa += a;
    sb += b;
    saa += a * a;
    sbb += b * b;
    sab += a * b;
  }
  const double n = static_cast<double>(samples.size());
  const double cov = sab - sa * sb / n, va = saa - sa * sa / n, vb = sbb - sb * sb / n;
  return va > 0 && vb > 0 ? cov / std::sqrt(va * vb) : 0.0;
}

std::vector<Sample> sampleImage(const CameraModel& camera, const cv::Mat& image, int step) {
  std::vector<Sample> samples;
  for (int y = step / 2; y < image.rows; y += step)
    for (int x = step / 2; x < image.cols; x += step) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      const double lum =
          luminance({srgbToLinear(p[2] / 255.0f), srgbToLinear(p[1] / 255.0f), srgbToLinear(p[0] / 255.0f)});
      samples.push_back(
          {camera.ray(vec2(static_cast<float>(x), static_cast<float>(y))).direction, std::log(1e-4 + lum)});
    }
  return samples;
}

}  // namespace

YawFit alignPanoramaYaw(const cv::Mat& panorama, const CameraModel& camera, const cv::Mat& image,
                        const std::string& source) {
  if (panorama.empty() || panorama.type() != CV_32FC3)
    throw InputError(source, "panorama", "a linear HDR panorama (CV_32FC3)");
  if (image.type() != CV_8UC3 || image.cols != camera.width() || image.rows != camera.height())
    throw InputError(source, "image", "an 8-bit colour image of the camera's size");
  const float degree = kPi / 180.0f;
  YawFit best{0.0f, -2.0};
  const std::vector<Sample> coarse = sampleImage(camera, image, 12);
  for (int d = -180; d < 180; ++d) {
    const double c = correlation(panorama, coarse, static_cast<float>(d) * degree);
    if (c > best.correlation) best = {static_cast<float>(d) * degree, c};
  }
  const std::vector<Sample> fine = sampleImage(camera, image, 3);
  const float centre = best.yaw_rad;
  best.correlation = -2.0;
  for (int k = -60; k <= 60; ++k) {
    const float yaw = centre + static_cast<float>(k) * 0.02f * degree;
    const double c = correlation(panorama, fine, yaw);
    if (c > best.correlation) best = {yaw, c};
  }
  if (best.yaw_rad >= kPi) best.yaw_rad -= 2 * kPi;
  if (best.yaw_rad < -kPi) best.yaw_rad += 2 * kPi;
  return best;
}

}  // namespace holo::calib
