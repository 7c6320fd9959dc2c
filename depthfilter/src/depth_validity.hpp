#pragma once

#include <limits>

namespace holo::depthfilter {

// A depth reading (metres) is valid when positive and finite; 0, negative, NaN and infinity mark
// "no reading". Written as two comparisons joined bitwise (NaN fails both) so the per-pixel loops
// that call it vectorise.
inline bool validDepth(float d) {
  return (d > 0.0f) & (d <= std::numeric_limits<float>::max());
}

}  // namespace holo::depthfilter
