// Seeded random numbers for one pixel sample: PCG32 (O'Neill) started from a hash of the seed,
// the pixel and the sample index, so a render is the same for a seed whatever the thread count.
#pragma once

#include <cstdint>

#include "holo/core/math.hpp"

namespace holo::ar {

class Random {
 public:
  Random(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    state_ = mix(seed ^ mix(pixel * 0x9E3779B97F4A7C15ull + sample));
    increment_ = (mix(pixel + 0x632BE59BD9B4E019ull * (sample + 1)) << 1u) | 1u;
    next();
  }
  std::uint32_t next() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  float uniform() { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }  // [0, 1)
  vec2 uniform2() { return {uniform(), uniform()}; }
  vec3 uniform3() { return {uniform(), uniform(), uniform()}; }

 private:
  static std::uint64_t mix(std::uint64_t z) {  // SplitMix64's finaliser
    z = (z ^ (z >> 30u)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27u)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31u);
  }
  std::uint64_t state_;
  std::uint64_t increment_;
};

}  // namespace holo::ar
