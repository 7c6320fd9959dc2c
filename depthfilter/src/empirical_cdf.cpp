#include "holo/depthfilter/empirical_cdf.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

EmpiricalCdf::EmpiricalCdf(int bins, float max_value) : max_value_(max_value) {
  if (bins < 1 || !(max_value > 0.0f) || !std::isfinite(max_value))
    throw Error("EmpiricalCdf: expected bins >= 1 and a finite max_value > 0");
  counts_.assign(static_cast<std::size_t>(bins), 0);
  cumulative_.assign(static_cast<std::size_t>(bins) + 1, 0.0f);
}

void EmpiricalCdf::add(float value) {
  if (!std::isfinite(value) || value < 0.0f) return;
  const int bin = std::min(bins() - 1, static_cast<int>(value / max_value_ * float(bins())));
  ++counts_[static_cast<std::size_t>(bin)];
  ++total_;
  dirty_ = true;
}

void EmpiricalCdf::rebuildCumulative() const {
  std::int64_t running = 0;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    cumulative_[i] = float(double(running) / double(total_));
    running += counts_[i];
  }
  cumulative_.back() = 1.0f;
  dirty_ = false;
}

}  // namespace holo::depthfilter
