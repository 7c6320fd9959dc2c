// A learned distribution of a non-negative quantity, stored as a histogram of `bins` equal bins
// over [0, max_value] (larger values fall into the last bin). The paper's PDF_alpha and PDF_|d|
// "expressed by enough discrete function values"; the filter reads them as cumulative
// probabilities P(X <= x). Invariant: cdf() returns a value in [0, 1] for every input, NaN included.
// Not thread-safe: cdf() rebuilds a cached cumulative table after add().
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace holo::depthfilter {

class EmpiricalCdf {
 public:
  EmpiricalCdf(int bins, float max_value);

  void add(float value);  // NaN/Inf and negative values are ignored
  std::int64_t samples() const { return total_; }
  // P(X <= value), linear inside a bin; 0 while nothing was learned. Inline: the filter reads
  // both distributions at every foreground pixel with a precursor.
  float cdf(float value) const {
    if (total_ == 0 || std::isnan(value) || value <= 0.0f) return 0.0f;
    if (value >= max_value_) return 1.0f;
    if (dirty_) rebuildCumulative();
    const float position = value / max_value_ * float(bins());
    const int bin = std::min(bins() - 1, static_cast<int>(position));
    const float t = position - float(bin);
    return cumulative_[std::size_t(bin)] +
           t * (cumulative_[std::size_t(bin) + 1] - cumulative_[std::size_t(bin)]);
  }
  float maxValue() const { return max_value_; }
  int bins() const { return static_cast<int>(counts_.size()); }

 private:
  void rebuildCumulative() const;

  std::vector<std::int64_t> counts_;
  mutable std::vector<float> cumulative_;  // rebuilt lazily after add()
  mutable bool dirty_ = true;
  float max_value_;
  std::int64_t total_ = 0;
};

}  // namespace holo::depthfilter
