#include "holo/reflect/distribution.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {

namespace {

// Index i with cdf[i] <= u < cdf[i+1], skipping zero-width cells.
int findInterval(const double* cdf, int n, double u) {
  const double* it = std::upper_bound(cdf + 1, cdf + n + 1, u);
  int i = static_cast<int>(it - cdf) - 1;
  i = std::clamp(i, 0, n - 1);
  while (i > 0 && cdf[i + 1] <= cdf[i]) --i;      // landed past the end on a flat tail
  while (i < n - 1 && cdf[i + 1] <= cdf[i]) ++i;  // landed on a flat cell
  return i;
}

}  // namespace

Distribution2D::Distribution2D(const std::vector<double>& weights, int width, int height)
    : width_(std::max(width, 0)), height_(std::max(height, 0)) {
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  weights_.assign(n, 0.0);
  for (std::size_t i = 0; i < n && i < weights.size(); ++i) {
    const double w = weights[i];
    weights_[i] = (std::isfinite(w) && w > 0) ? w : 0.0;
  }
  row_sums_.assign(static_cast<std::size_t>(height_), 0.0);
  row_cdf_.assign(static_cast<std::size_t>(height_) + 1, 0.0);
  column_cdfs_.assign(static_cast<std::size_t>(height_) * (static_cast<std::size_t>(width_) + 1), 0.0);
  for (int y = 0; y < height_; ++y) {
    double* cdf = &column_cdfs_[static_cast<std::size_t>(y) * (width_ + 1)];
    const double* w = &weights_[static_cast<std::size_t>(y) * width_];
    for (int x = 0; x < width_; ++x) cdf[x + 1] = cdf[x] + w[x];
    const double sum = cdf[width_];
    row_sums_[y] = sum;
    for (int x = 1; x <= width_; ++x) cdf[x] = sum > 0 ? cdf[x] / sum : double(x) / width_;
    row_cdf_[y + 1] = row_cdf_[y] + sum;
  }
  total_ = height_ > 0 ? row_cdf_[height_] : 0.0;
  for (int y = 1; y <= height_; ++y) row_cdf_[y] = total_ > 0 ? row_cdf_[y] / total_ : 0.0;
}

Distribution2D::Sample Distribution2D::sample(const vec2& u) const {
  Sample s;
  if (empty()) return s;
  const double uy = std::clamp(double(u.y), 0.0, 1.0);
  s.y = findInterval(row_cdf_.data(), height_, uy);
  const double row_lo = row_cdf_[s.y], row_hi = row_cdf_[s.y + 1];
  const double* cdf = &column_cdfs_[static_cast<std::size_t>(s.y) * (width_ + 1)];
  const double ux = std::clamp(double(u.x), 0.0, 1.0);
  s.x = findInterval(cdf, width_, ux);
  const double col_lo = cdf[s.x], col_hi = cdf[s.x + 1];
  s.within.x = float(std::clamp((ux - col_lo) / std::max(col_hi - col_lo, 1e-300), 0.0, 0.99999994));
  s.within.y = float(std::clamp((uy - row_lo) / std::max(row_hi - row_lo, 1e-300), 0.0, 0.99999994));
  s.probability = probability(s.x, s.y);
  return s;
}

double Distribution2D::probability(int x, int y) const {
  if (empty() || x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0;
  return weights_[static_cast<std::size_t>(y) * width_ + x] / total_;
}

}  // namespace holo::reflect
