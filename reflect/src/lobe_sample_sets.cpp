#include "lobe_sample_sets.hpp"

namespace holo::reflect {

vec2 stratumOffset(std::uint32_t set, std::size_t pixel, int sample) {
  const std::uint64_t h =
      splitMixFinaliser(std::uint64_t(pixel) * 8u + std::uint64_t(sample) + 0x9e3779b97f4a7c15ull);
  // Sobol's first two dimensions from a point of its own per sample (a (0, 2)-sequence: any 2^k
  // consecutive points from a multiple of 2^k stratify the square into any 2^k equal boxes),
  // digitally shifted per sample.
  std::uint32_t x = 0, y = 0;
  for (std::uint32_t n = set + std::uint32_t(h >> 54), bit = 1u << 31, v = 1u << 31; n;
       n >>= 1, bit >>= 1, v ^= v >> 1)
    if (n & 1u) {
      x |= bit;
      y ^= v;
    }
  x ^= std::uint32_t(h);
  y ^= std::uint32_t(h >> 32);
  return vec2(float(x >> 8) * (1.0f / 16777216.0f), float(y >> 8) * (1.0f / 16777216.0f));
}

}  // namespace holo::reflect
