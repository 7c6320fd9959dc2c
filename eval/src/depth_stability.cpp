#include "holo/eval/depth_stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr float kDepthBand = 0.2f;  // a background pixel counts for depth Z within 20% of it

// Valid pixels with a 4-neighbour that is a hole or differs by more than 0.05 m + 5% of the depth.
cv::Mat depthEdges(const cv::Mat& depth) {
  cv::Mat edges = cv::Mat::zeros(depth.size(), CV_8UC1);
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const float z = depth.at<float>(y, x);
      if (!(z > 0.0f)) continue;
      for (int k = 0; k < 4; ++k) {
        const int nx = x + dx[k], ny = y + dy[k];
        if (nx < 0 || ny < 0 || nx >= depth.cols || ny >= depth.rows) continue;
        const float zn = depth.at<float>(ny, nx);
        if (!(zn > 0.0f) || std::abs(zn - z) > 0.05f + 0.05f * std::min(z, zn)) {
          edges.at<std::uint8_t>(y, x) = 255;
          break;
        }
      }
    }
  return edges;
}

// Sum over the edge pixels of `from` inside `region` of the distance to the nearest edge pixel
// of `to`, each clipped at kMaxEdgeJitterPx; adds their number to `count`.
double edgeDistances(const cv::Mat& from, const cv::Mat& to, const cv::Mat& region, long long& count) {
  cv::Mat distance;
  if (cv::countNonZero(to) == 0) {
    distance = cv::Mat(to.size(), CV_32FC1, cv::Scalar(kMaxEdgeJitterPx));
  } else {
    cv::distanceTransform(~to, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  }
  double sum = 0;
  for (int y = 0; y < from.rows; ++y)
    for (int x = 0; x < from.cols; ++x)
      if (from.at<std::uint8_t>(y, x) && region.at<std::uint8_t>(y, x)) {
        sum += std::min(distance.at<float>(y, x), kMaxEdgeJitterPx);
        ++count;
      }
  return sum;
}

double median(std::vector<float> values) {
  if (values.empty()) return kNaN;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

EdgeAndFlicker finish(long long switches, long long pairs, double edge_distance, long long edge_pixels) {
  EdgeAndFlicker f;
  f.pixel_pairs = pairs;
  f.hole_flicker = pairs > 0 ? double(switches) / double(pairs) : kNaN;
  f.edge_pixels = edge_pixels;
  f.edge_jitter_px = edge_pixels > 0 ? edge_distance / double(edge_pixels) : kNaN;
  return f;
}

}  // namespace

DepthStabilityMeter::DepthStabilityMeter(DepthStabilityConfig config) : config_(config) {}

void DepthStabilityMeter::accumulate(Sums& sums, const cv::Mat& previous, const cv::Mat& current,
                                     const cv::Mat& region, cv::Mat* switch_count) {
  const cv::Mat switched = ((previous > 0.0f) != (current > 0.0f)) & region;
  sums.switches += cv::countNonZero(switched);
  sums.pairs += cv::countNonZero(region);
  if (switch_count) cv::add(*switch_count, 1, *switch_count, switched);
  const cv::Mat edges_now = depthEdges(current), edges_before = depthEdges(previous);
  sums.edge_distance += edgeDistances(edges_now, edges_before, region, sums.edge_pixels);
  sums.edge_distance += edgeDistances(edges_before, edges_now, region, sums.edge_pixels);
}

void DepthStabilityMeter::addFrame(const cv::Mat& raw, const cv::Mat& mask, const cv::Mat& filtered) {
  if (raw.type() != CV_32FC1 || filtered.type() != CV_32FC1 || mask.type() != CV_8UC1 ||
      raw.size() != mask.size() || raw.size() != filtered.size())
    throw Error(
        "DepthStabilityMeter: raw and filtered depth must be CV_32FC1 and the mask CV_8UC1, of one size");
  if (!background_count_.empty() && raw.size() != background_count_.size())
    throw Error("DepthStabilityMeter: a frame's size differs from the first frame's");
  if (background_count_.empty()) {
    background_sum_ = cv::Mat::zeros(raw.size(), CV_64FC1);
    background_sum_sq_ = cv::Mat::zeros(raw.size(), CV_64FC1);
    background_count_ = cv::Mat::zeros(raw.size(), CV_32SC1);
    raw_switches_ = cv::Mat::zeros(raw.size(), CV_32SC1);
    filtered_switches_ = cv::Mat::zeros(raw.size(), CV_32SC1);
  }
  const cv::Mat foreground = mask != 0;
  // NaN or Inf reads as a hole.
  cv::Mat raw_clean = raw.clone(), filtered_clean = filtered.clone();
  raw_clean.setTo(0.0f, ~(raw == raw) | (raw > std::numeric_limits<float>::max()));
  filtered_clean.setTo(0.0f, ~(filtered == filtered) | (filtered > std::numeric_limits<float>::max()));

  for (int y = 0; y < raw.rows; ++y)
    for (int x = 0; x < raw.cols; ++x) {
      const float z = raw_clean.at<float>(y, x);
      if (foreground.at<std::uint8_t>(y, x) || !(z > 0.0f)) continue;
      background_sum_.at<double>(y, x) += z;
      background_sum_sq_.at<double>(y, x) += double(z) * z;
      ++background_count_.at<int>(y, x);
    }
  if (!previous_raw_.empty()) {
    const cv::Mat both_foreground = foreground & previous_mask_;
    const cv::Mat both_background = ~foreground & ~previous_mask_;
    accumulate(raw_, previous_raw_, raw_clean, both_foreground, &raw_switches_);
    accumulate(filtered_, previous_filtered_, filtered_clean, both_foreground, &filtered_switches_);
    accumulate(background_, previous_raw_, raw_clean, both_background, nullptr);
    ++frame_pairs_;
  }
  previous_raw_ = raw_clean;
  previous_filtered_ = filtered_clean;
  previous_mask_ = foreground;
}

bool DepthStabilityMeter::backgroundPixel(int x, int y, float& mean_m, float& std_mm) const {
  const int n = background_count_.at<int>(y, x);
  if (n < std::max(2, config_.min_background_samples)) return false;
  const double mean = background_sum_.at<double>(y, x) / n;
  const double variance = std::max(0.0, (background_sum_sq_.at<double>(y, x) - n * mean * mean) / (n - 1));
  mean_m = float(mean);
  std_mm = float(1000.0 * std::sqrt(variance));
  return true;
}

cv::Mat DepthStabilityMeter::backgroundNoiseMm() const {
  cv::Mat out = cv::Mat::zeros(background_count_.size(), CV_32FC1);
  float mean = 0, std_mm = 0;
  for (int y = 0; y < background_count_.rows; ++y)
    for (int x = 0; x < background_count_.cols; ++x)
      if (backgroundPixel(x, y, mean, std_mm)) out.at<float>(y, x) = std_mm;
  return out;
}

DepthStabilityFigures DepthStabilityMeter::figures() const {
  return combined({*this});
}

DepthStabilityFigures DepthStabilityMeter::combined(const std::vector<DepthStabilityMeter>& meters) {
  Sums raw, filtered, background;
  DepthStabilityFigures f;
  std::vector<float> all;
  std::array<std::vector<float>, kBackgroundNoiseDepths.size()> at_depth;
  for (const DepthStabilityMeter& m : meters) {
    for (auto [total, part] :
         {std::pair{&raw, &m.raw_}, {&filtered, &m.filtered_}, {&background, &m.background_}}) {
      total->switches += part->switches;
      total->pairs += part->pairs;
      total->edge_distance += part->edge_distance;
      total->edge_pixels += part->edge_pixels;
    }
    f.frame_pairs += m.frame_pairs_;
    float depth = 0, std_mm = 0;
    for (int y = 0; y < m.background_count_.rows; ++y)
      for (int x = 0; x < m.background_count_.cols; ++x) {
        if (!m.backgroundPixel(x, y, depth, std_mm)) continue;
        all.push_back(std_mm);
        for (std::size_t k = 0; k < kBackgroundNoiseDepths.size(); ++k)
          if (std::abs(depth - kBackgroundNoiseDepths[k]) <= kDepthBand * kBackgroundNoiseDepths[k])
            at_depth[k].push_back(std_mm);
      }
  }
  f.raw = finish(raw.switches, raw.pairs, raw.edge_distance, raw.edge_pixels);
  f.filtered = finish(filtered.switches, filtered.pairs, filtered.edge_distance, filtered.edge_pixels);
  f.background =
      finish(background.switches, background.pairs, background.edge_distance, background.edge_pixels);
  f.background_noise_pixels = static_cast<long long>(all.size());
  f.background_noise_mm = median(std::move(all));
  for (std::size_t k = 0; k < kBackgroundNoiseDepths.size(); ++k)
    f.background_noise_mm_at[k] = median(std::move(at_depth[k]));
  return f;
}

}  // namespace holo::eval
