#include "holo/reference/sampler.hpp"

namespace holo::reference {

namespace {

std::uint32_t reverseBits(std::uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

// Laine-Karras style hash that only lets lower bits influence higher ones.
std::uint32_t laineKarras(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Owen scrambling of the bits of x from the most significant one down.
std::uint32_t nestedUniformScramble(std::uint32_t x, std::uint32_t seed) {
  return reverseBits(laineKarras(reverseBits(x), seed));
}

std::uint32_t sobolSecondDimension(std::uint32_t i) {
  std::uint32_t r = 0;
  for (std::uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1u) r ^= v;
  return r;
}

float toUnitFloat(std::uint32_t x) {
  return float(x >> 8) * 0x1p-24f;
}  // in [0, 1)

}  // namespace

std::uint32_t hashCombine(std::uint32_t seed, std::uint32_t value) {
  // PCG-style integer hash of the pair (Jarzynski & Olano 2020).
  std::uint32_t h = seed ^ (value + 0x9e3779b9u + (seed << 6) + (seed >> 2));
  h = h * 747796405u + 2891336453u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  return (h >> 22u) ^ h;
}

SampleStream::SampleStream(std::uint64_t seed, std::uint32_t pixel, std::uint32_t sample_index)
    : base_(hashCombine(hashCombine(std::uint32_t(seed), std::uint32_t(seed >> 32)), pixel)),
      index_(sample_index) {}

vec2 SampleStream::next2D() {
  const std::uint32_t pair_seed = hashCombine(base_, dimension_++);
  const std::uint32_t shuffled = nestedUniformScramble(index_, pair_seed);
  const std::uint32_t x = nestedUniformScramble(reverseBits(shuffled), hashCombine(pair_seed, 1));
  const std::uint32_t y = nestedUniformScramble(sobolSecondDimension(shuffled), hashCombine(pair_seed, 2));
  return {toUnitFloat(x), toUnitFloat(y)};
}

}  // namespace holo::reference
