// The median as the project's reports and benchmarks quote it: for an even count the upper of
// the two middle values (always a value that occurred, never an average); 0 for no values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace holo {

inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace holo
