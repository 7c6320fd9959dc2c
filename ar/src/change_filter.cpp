#include "holo/ar/change_filter.hpp"

#include <tbb/parallel_for.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::ar {
namespace {

// 255 where a pixel's window (2 radius + 1)^2 holds a change: elsewhere the filtered value is the
// pixel's own (background + 0), so only the neighbourhood of what the relic changes is filtered.
cv::Mat nearChange(const cv::Mat& change, int radius) {
  std::vector<cv::Mat> channels;
  cv::split(change, channels);
  cv::Mat near = (channels[0] != 0.0f) | (channels[1] != 0.0f) | (channels[2] != 0.0f);
  const int side = 2 * radius + 1;
  cv::dilate(near, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  return near;
}

}  // namespace

cv::Mat filterChange(const cv::Mat& composite, const cv::Mat& background, const cv::Mat& relic_coverage,
                     const cv::Mat& depth, const ChangeFilterSettings& s) {
  if (background.size() != composite.size() || relic_coverage.size() != composite.size() ||
      depth.size() != composite.size() || composite.type() != CV_32FC3 || background.type() != CV_32FC3 ||
      relic_coverage.type() != CV_32FC1 || depth.type() != CV_32FC1)
    throw InputError("AR change filter", "images",
                     "composite and background CV_32FC3, coverage and depth CV_32FC1, all of one size");
  cv::Mat out = composite.clone();
  if (!s.enabled || s.radius < 1) return out;
  const cv::Mat change = composite - background;
  const cv::Mat near_change = nearChange(change, s.radius);
  std::vector<float> weights;
  for (int dy = -s.radius; dy <= s.radius; ++dy)
    for (int dx = -s.radius; dx <= s.radius; ++dx)
      weights.push_back(std::exp(-0.5f * static_cast<float>(dx * dx + dy * dy) / (s.sigma * s.sigma)));
  const auto real = [&](int x, int y) {
    return relic_coverage.at<float>(y, x) == 0.0f && depth.at<float>(y, x) > 0.0f;
  };
  tbb::parallel_for(0, composite.rows, [&](int y) {
    for (int x = 0; x < composite.cols; ++x) {
      if (!real(x, y) || near_change.at<std::uint8_t>(y, x) == 0) continue;
      const float d = depth.at<float>(y, x);
      vec3 sum(0.0f);
      float total = 0.0f;
      std::size_t k = 0;
      for (int dy = -s.radius; dy <= s.radius; ++dy)
        for (int dx = -s.radius; dx <= s.radius; ++dx, ++k) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= composite.cols || ny >= composite.rows || !real(nx, ny)) continue;
          if (std::abs(depth.at<float>(ny, nx) - d) > s.max_depth_ratio * d) continue;
          sum += weights[k] * rgbAt(change, nx, ny);
          total += weights[k];
        }
      setRgb(out, x, y, rgbAt(background, x, y) + sum / total);
    }
  });
  return out;
}

}  // namespace holo::ar
