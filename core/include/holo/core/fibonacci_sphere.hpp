// Evenly spread unit directions over the sphere (the Fibonacci lattice): deterministic probe
// directions for measurements that average over all directions.
#pragma once

#include <algorithm>
#include <cmath>

#include "holo/core/math.hpp"

namespace holo {

// Direction i of n (0 <= i < n): n rings of equal area from near +y (i = 0) to near -y, each
// turned from the one before by the golden angle.
inline vec3 fibonacciDirection(int i, int n) {
  const float golden = kPi * (3.0f - std::sqrt(5.0f));
  const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
  const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
  return vec3(r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i)));
}

}  // namespace holo
