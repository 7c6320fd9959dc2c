// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// Seeded low-discrepancy sample streams for Monte Carlo rendering: per pixel, an Owen-scrambled
// Sobol (0,2) sequence for every pair of dimensions, with the sample index shuffled per pixel and
// per dimension pair (Burley 2020, "Practical Hash-based Owen Scrambling"). Every power-of-two
// prefix of a pixel's samples stays stratified, dimension pairs are decorrelated, and the values
// depend only on (seed, pixel, sample index, dimension): renders are bit-identical for a seed,
// whatever the tiling or thread count, and progressive passes continue the same sequence.
#pragma once

#include <cstdint>

#include "holo/core/math.hpp"

namespace holo::reference {

std::uint32_t hashCombine(std::uint32_t seed, std::uint32_t value);

class SampleStream {
 public:
  SampleStream(std::uint64_t seed, std::uint32_t pixel, std::uint32_t sample_index);
  vec2 next2D();  // in [0,1)^2; consecutive calls use new dimension pairs
  float next1D() { return next2D().x; }
  vec3 next3D() {  // one 2D pair plus the first coordinate of the next
    const vec2 a = next2D();
    return {a.x, a.y, next1D()};
  }

 private:
  std::uint32_t base_;
  std::uint32_t index_;
  std::uint32_t dimension_ = 0;
};

}  // namespace holo::reference
