// A learned distribution of a non-negative quantity, stored as a histogram of `bins` equal bins
// over [0, max_value] (larger values fall into the last bin). The paper's PDF_alpha and PDF_|d|
// "expressed by enough discrete function values"; the filter reads them as cumulative
// probabilities P(X <= x). Invariant: cdf() returns a value in [0, 1] for every input, NaN included.
// Not thread-safe: cdf() rebuilds a cached cumulative table after add().
#pragma once

#include <cstdint>
#include <vector>

namespace holo::depthfilter {

class EmpiricalCdf {
 public:
  EmpiricalCdf(int bins, float max_value);

  void add(float value);  // NaN/Inf and negative values are ignored
  std::int64_t samples() const { return total_; }
  // P(X <= value), linear inside a bin; 0 while nothing was learned.
  float cdf(float value) const;
  float maxValue() const { return max_value_; }
  int bins() const { return static_cast<int>(counts_.size()); }

 private:
  std::vector<std::int64_t> counts_;
  mutable std::vector<float> cumulative_;  // rebuilt lazily after add()
  mutable bool dirty_ = true;
  float max_value_;
  std::int64_t total_ = 0;
};

}  // namespace holo::depthfilter
