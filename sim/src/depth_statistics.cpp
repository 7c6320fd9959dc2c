#include "holo/sim/depth_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "holo/core/error.hpp"

namespace holo::sim {

namespace {

constexpr int kWindowRadius = 3;  // 7 x 7 noise windows
constexpr int kWindowStride = 4;
constexpr float kDepthBand = 0.2f;  // a window counts for Z when its mean is within 20% of Z

bool isJump(float a, float b) {
  return std::abs(a - b) > 0.05f + 0.05f * std::min(a, b);
}

// Marks both valid pixels of every jump between consecutive valid pixels of a row or column that
// are at most kMaxGap holes apart.
cv::Mat edgeMap(const cv::Mat& depth) {
  cv::Mat edges = cv::Mat::zeros(depth.size(), CV_8UC1);
  const auto scan = [&](int count, int length, auto at) {
    for (int line = 0; line < count; ++line) {
      int previous = -1;
      for (int i = 0; i < length; ++i) {
        const auto [x, y] = at(line, i);
        const float z = depth.at<float>(y, x);
        if (z <= 0.0f) continue;
        if (previous >= 0 && i - previous - 1 <= kMaxGap) {
          const auto [px, py] = at(line, previous);
          if (isJump(z, depth.at<float>(py, px))) {
            edges.at<std::uint8_t>(y, x) = 255;
            edges.at<std::uint8_t>(py, px) = 255;
          }
        }
        previous = i;
      }
    }
  };
  scan(depth.rows, depth.cols, [](int row, int i) { return std::pair{i, row}; });
  scan(depth.cols, depth.rows, [](int column, int i) { return std::pair{column, i}; });
  return edges;
}

// RMS residual of the least-squares plane over the 7 x 7 window centred at (x, y), or < 0 when a
// pixel is missing or on an edge. On the symmetric grid the three normal equations decouple.
double windowResidual(const cv::Mat& depth, const cv::Mat& edges, int x, int y, double& mean) {
  constexpr int n = (2 * kWindowRadius + 1) * (2 * kWindowRadius + 1);
  double values[n];
  int i = 0;
  double sum = 0;
  for (int v = -kWindowRadius; v <= kWindowRadius; ++v)
    for (int u = -kWindowRadius; u <= kWindowRadius; ++u) {
      const float z = depth.at<float>(y + v, x + u);
      if (z <= 0.0f || edges.at<std::uint8_t>(y + v, x + u)) return -1.0;
      values[i++] = z;
      sum += z;
    }
  mean = sum / n;
  double ss = 0, su = 0, sv = 0, s_uu = 0;
  i = 0;
  for (int v = -kWindowRadius; v <= kWindowRadius; ++v)
    for (int u = -kWindowRadius; u <= kWindowRadius; ++u) {
      const double r = values[i++] - mean;
      ss += r * r;
      su += u * r;
      sv += v * r;
      s_uu += u * u;
    }
  const double residual = std::max(0.0, ss - su * su / s_uu - sv * sv / s_uu);
  return std::sqrt(residual / (n - 3));
}

}  // namespace

DepthStatistics measureDepthStatistics(const cv::Mat& depth, const cv::Mat& person) {
  return measureDepthStatistics(std::vector<cv::Mat>{depth}, std::vector<cv::Mat>{person});
}

DepthStatistics measureDepthStatistics(const std::vector<cv::Mat>& depths,
                                       const std::vector<cv::Mat>& persons) {
  CV_Assert(persons.empty() || persons.size() == depths.size());
  DepthStatistics s;
  long long pixels = 0, holes_total = 0, edge_holes = 0;
  long long on_pixels = 0, on_holes = 0, off_pixels = 0, off_holes = 0;
  std::array<double, kHoleSizeBounds.size() + 1> size_pixels{};
  std::array<std::vector<double>, kNoiseDepths.size()> residuals;
  std::vector<float> valid_depths;
  const cv::Mat window =
      cv::getStructuringElement(cv::MORPH_RECT, {2 * kEdgeRadius + 1, 2 * kEdgeRadius + 1});
  for (std::size_t f = 0; f < depths.size(); ++f) {
    const cv::Mat& depth = depths[f];
    const cv::Mat person = persons.empty() ? cv::Mat() : persons[f];
    CV_Assert(depth.type() == CV_32FC1);
    CV_Assert(person.empty() || (person.type() == CV_8UC1 && person.size() == depth.size()));
    pixels += static_cast<long long>(depth.total());
    const cv::Mat holes = depth <= 0.0f;
    holes_total += cv::countNonZero(holes);
    const cv::Mat edges = edgeMap(depth);
    cv::Mat near_edge;
    cv::dilate(edges, near_edge, window);
    edge_holes += cv::countNonZero(holes & near_edge);
    if (!person.empty()) {
      const cv::Mat on = person != 0;
      on_pixels += cv::countNonZero(on);
      on_holes += cv::countNonZero(holes & on);
      off_pixels += static_cast<long long>(depth.total()) - cv::countNonZero(on);
      off_holes += cv::countNonZero(holes & ~on);
    }
    cv::Mat labels, stats, centroids;
    const int components = cv::connectedComponentsWithStats(holes, labels, stats, centroids, 8, CV_32S);
    s.hole_components += components - 1;
    for (int c = 1; c < components; ++c) {
      const int area = stats.at<int>(c, cv::CC_STAT_AREA);
      std::size_t k = 0;
      while (k < kHoleSizeBounds.size() && area > kHoleSizeBounds[k]) ++k;
      size_pixels[k] += area;
    }
    for (int y = kWindowRadius; y < depth.rows - kWindowRadius; y += kWindowStride)
      for (int x = kWindowRadius; x < depth.cols - kWindowRadius; x += kWindowStride) {
        double mean = 0;
        const double r = windowResidual(depth, edges, x, y, mean);
        if (r < 0) continue;
        for (std::size_t k = 0; k < kNoiseDepths.size(); ++k)
          if (std::abs(mean - kNoiseDepths[k]) <= kDepthBand * kNoiseDepths[k]) residuals[k].push_back(r);
      }
    for (int y = 0; y < depth.rows; ++y)
      for (int x = 0; x < depth.cols; ++x)
        if (const float z = depth.at<float>(y, x); z > 0.0f) valid_depths.push_back(z);
  }
  s.pixels = pixels;
  if (pixels == 0) return s;
  s.hole_fraction = static_cast<double>(holes_total) / static_cast<double>(pixels);
  if (holes_total > 0) s.edge_hole_share = static_cast<double>(edge_holes) / static_cast<double>(holes_total);
  if (!persons.empty()) {
    if (on_pixels > 0)
      s.person_hole_fraction = static_cast<double>(on_holes) / static_cast<double>(on_pixels);
    if (off_pixels > 0)
      s.other_hole_fraction = static_cast<double>(off_holes) / static_cast<double>(off_pixels);
  }
  for (std::size_t k = 0; k < size_pixels.size(); ++k)
    s.hole_size_share[k] = holes_total > 0 ? size_pixels[k] / static_cast<double>(holes_total) : 0.0;
  for (std::size_t k = 0; k < kNoiseDepths.size(); ++k) {
    auto& r = residuals[k];
    s.noise_windows[k] = static_cast<int>(r.size());
    if (static_cast<int>(r.size()) < kMinNoiseWindows) {
      s.noise[k] = -1.0;
      continue;
    }
    std::nth_element(r.begin(), r.begin() + static_cast<long>(r.size() / 2), r.end());
    s.noise[k] = r[r.size() / 2];
  }
  if (!valid_depths.empty()) {
    std::nth_element(valid_depths.begin(), valid_depths.begin() + static_cast<long>(valid_depths.size() / 2),
                     valid_depths.end());
    s.median_depth = valid_depths[valid_depths.size() / 2];
  }
  return s;
}

cv::Mat loadDepthPng(const std::string& path, double units_per_metre) {
  const cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (raw.empty()) throw InputError(path, "depth", "a readable 16-bit depth PNG", "unreadable or missing");
  if (raw.type() != CV_16UC1)
    throw InputError(path, "depth", "a 16-bit single-channel PNG", "type " + std::to_string(raw.type()));
  cv::Mat metres;
  raw.convertTo(metres, CV_32FC1, 1.0 / units_per_metre);
  return metres;
}

std::string describe(const DepthStatistics& s) {
  std::ostringstream o;
  o.precision(3);
  o << "holes " << 100 * s.hole_fraction << "% of " << s.pixels << " px, " << 100 * s.edge_hole_share
    << "% within " << kEdgeRadius << " px of a depth edge, " << s.hole_components << " components";
  if (s.person_hole_fraction >= 0)
    o << ", on people " << 100 * s.person_hole_fraction << "%, elsewhere " << 100 * s.other_hole_fraction
      << "%";
  o << "\nhole pixels in components of 1 / 2-10 / 11-100 / 101-1000 / >1000 px:";
  for (double share : s.hole_size_share) o << " " << 100 * share << "%";
  o << "\nnoise:";
  for (std::size_t k = 0; k < kNoiseDepths.size(); ++k) {
    o << " at " << kNoiseDepths[k] << " m ";
    if (s.noise[k] < 0)
      o << "-";
    else
      o << 1000 * s.noise[k] << " mm";
    o << " (" << s.noise_windows[k] << " windows)";
  }
  o << "; median depth " << s.median_depth << " m";
  return o.str();
}

}  // namespace holo::sim
