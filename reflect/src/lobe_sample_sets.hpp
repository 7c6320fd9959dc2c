// Where each rough-lobe sample reads its strata (static_shading.hpp): sample set n's point within
// every stratum of pixel p's sample s is point n + phi(p, s) of Sobol's first two dimensions,
// digitally shifted (XOR) by a hash of (p, s). Set 0 is what a moving view shows, the same in every
// frame (the thesis' preview mode keeps the same random parameters each frame for temporal
// coherence; the strata's centres would be a midpoint rule that misses the lobe's tails); sets
// 1, 2, ... are what a still view accumulates (progressive_accumulation.hpp). Each sample runs
// through the sequence from a phase phi of its own (0..1023), so that the pixels' errors do not
// rise and fall together with the sequence's stratification, and the shifts keep neighbouring
// pixels (which the tent pools) from erring alike. Deterministic per set.
#pragma once

#include <cstddef>
#include <cstdint>

#include "holo/core/math.hpp"

namespace holo::reflect {

// splitmix64's finaliser: a 64-bit hash whose every output bit depends on every input bit.
inline std::uint64_t splitMixFinaliser(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Sample set `set`'s offset within each stratum for sample `sample` of pixel `pixel`, in [0, 1)^2.
vec2 stratumOffset(std::uint32_t set, std::size_t pixel, int sample);

}  // namespace holo::reflect
