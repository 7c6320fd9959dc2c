#include "holo/ar/change_filter.hpp"

#include <tbb/parallel_for.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "holo/core/error.hpp"

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
  // Real pixels (no sample met the relic, valid depth), 1 or 0.
  const cv::Mat real = (relic_coverage == 0.0f) & (depth > 0.0f);
  const int side = 2 * s.radius + 1;
  tbb::parallel_for(0, composite.rows, [&](int y) {
    const std::uint8_t* real_row = real.ptr<std::uint8_t>(y);
    const std::uint8_t* near_row = near_change.ptr<std::uint8_t>(y);
    const float* depth_row = depth.ptr<float>(y);
    const float* background_row = background.ptr<float>(y);
    float* out_row = out.ptr<float>(y);
    const int y0 = std::max(0, y - s.radius), y1 = std::min(composite.rows - 1, y + s.radius);
    for (int x = 0; x < composite.cols; ++x) {
      if (real_row[x] == 0 || near_row[x] == 0) continue;
      const float d = depth_row[x];
      const float reach = s.max_depth_ratio * d;
      const int x0 = std::max(0, x - s.radius), x1 = std::min(composite.cols - 1, x + s.radius);
      float sum[3] = {0.0f, 0.0f, 0.0f};
      float total = 0.0f;
      for (int ny = y0; ny <= y1; ++ny) {
        const std::uint8_t* real_near = real.ptr<std::uint8_t>(ny);
        const float* depth_near = depth.ptr<float>(ny);
        const float* change_near = change.ptr<float>(ny);
        const float* weight =
            &weights[static_cast<std::size_t>((ny - y + s.radius) * side + (x0 - x + s.radius))];
        for (int nx = x0; nx <= x1; ++nx, ++weight) {
          if (real_near[nx] == 0 || std::abs(depth_near[nx] - d) > reach) continue;
          for (int c = 0; c < 3; ++c) sum[c] += *weight * change_near[3 * nx + c];
          total += *weight;
        }
      }
      for (int c = 0; c < 3; ++c) out_row[3 * x + c] = background_row[3 * x + c] + sum[c] / total;
    }
  });
  return out;
}

}  // namespace holo::ar
