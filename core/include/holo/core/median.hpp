// The median as the project's reports and benchmarks quote it: for an even count the upper of
// the two middle values (always a value that occurred, never an average); 0 for no values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace holo {

// The same rule on any ordered type, reordering `values` instead of copying them (per-pixel
// loops); T{} for no values.
template <typename T>
T medianInPlace(std::vector<T>& values) {
  if (values.empty()) return T{};
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

inline double median(std::vector<double> values) {
  return medianInPlace(values);
}

}  // namespace holo
