#include "holo/sim/sensor_noise.hpp"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>

#include "holo/core/image.hpp"

namespace holo::sim {

namespace {

std::uint64_t splitmix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

PixelRng::PixelRng(std::uint64_t seed, std::uint64_t stream, int x, int y) {
  std::uint64_t h = seed;
  h = splitmix(h) ^ stream;
  h = splitmix(h) ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(x));
  h = splitmix(h) ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(y)) << 32);
  state_ = splitmix(h);
}

std::uint64_t PixelRng::next() {
  return splitmix(state_);
}

float PixelRng::uniform() {
  return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f);
}

float PixelRng::normal() {
  const float u1 = 1.0f - uniform();  // (0, 1]: log stays finite
  const float u2 = uniform();
  return std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * kPi * u2);
}

float depthSigma(const SensorNoise& noise, float z) {
  return noise.sigma_0 + noise.k_z2 * z * z;
}

bool isDepthEdge(const cv::Mat& true_depth, int x, int y) {
  const float z = true_depth.at<float>(y, x);
  if (z <= 0.0f) return false;
  const float threshold = 0.05f + 0.05f * z;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx < 0 || ny < 0 || nx >= true_depth.cols || ny >= true_depth.rows) continue;
    const float zn = true_depth.at<float>(ny, nx);
    if (zn <= 0.0f || std::abs(zn - z) > threshold) return true;
  }
  return false;
}

namespace {

// The valid neighbour farthest in depth, for a flying pixel's mixed depth (z itself if none).
float farthestNeighbour(const cv::Mat& depth, int x, int y) {
  const float z = depth.at<float>(y, x);
  float best = z;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx < 0 || ny < 0 || nx >= depth.cols || ny >= depth.rows) continue;
    const float zn = depth.at<float>(ny, nx);
    if (zn > 0.0f && std::abs(zn - z) > std::abs(best - z)) best = zn;
  }
  return best;
}

std::uint8_t toByte(float v) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

}  // namespace

SensorOutput applySensorNoise(const SensorNoise& noise, const CameraSettings& camera,
                              const cv::Mat& true_depth, const cv::Mat& cos_incidence,
                              const cv::Mat& radiance, std::uint64_t seed) {
  CV_Assert(true_depth.type() == CV_32FC1 && cos_incidence.type() == CV_32FC1 && radiance.type() == CV_32FC3);
  CV_Assert(true_depth.size() == cos_incidence.size() && true_depth.size() == radiance.size());
  SensorOutput out;
  out.depth = cv::Mat::zeros(true_depth.size(), CV_32FC1);
  out.color = cv::Mat(true_depth.size(), CV_8UC3);
  const float cos_grazing = std::cos(noise.grazing_dropout_deg * kPi / 180.0f);
  tbb::parallel_for(0, true_depth.rows, [&](int y) {
    for (int x = 0; x < true_depth.cols; ++x) {
      PixelRng rng(seed, 0x5e4502ull, x, y);
      const cv::Vec3f& rad = radiance.at<cv::Vec3f>(y, x);
      cv::Vec3b& bgr = out.color.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const float encoded = 255.0f * linearToSrgb(std::max(0.0f, camera.exposure * rad[c]));
        bgr[c] = toByte(noise.enabled ? encoded + noise.color_sigma * rng.normal() : encoded);
      }
      const float z = true_depth.at<float>(y, x);
      if (!noise.enabled) {
        out.depth.at<float>(y, x) = z;
        continue;
      }
      if (z <= 0.0f) continue;
      if (rng.uniform() < noise.random_dropout) continue;
      if (cos_incidence.at<float>(y, x) < cos_grazing) continue;
      float base = z;
      if (isDepthEdge(true_depth, x, y)) {
        if (rng.uniform() < noise.edge_dropout) continue;
        if (rng.uniform() < noise.flying_pixel)
          base = z + (0.15f + 0.7f * rng.uniform()) * (farthestNeighbour(true_depth, x, y) - z);
      }
      const float measured = base + depthSigma(noise, base) * rng.normal();
      if (measured >= camera.min_range && measured <= camera.max_range) out.depth.at<float>(y, x) = measured;
    }
  });
  return out;
}

}  // namespace holo::sim
