// Square octahedral maps of directions (Engelhardt & Dachsbacher 2008): the storage of the
// prefiltered IBL, not a panorama format (panoramas use core/equirect.hpp only). The upper
// hemisphere (+Y) fills the inner diamond, the lower one the folded corners. Texels cover nearly
// equal solid angles (within a factor ~2), which is why the FIS level formula can treat a texel
// as 4 pi / size^2 steradians. Bilinear lookups wrap across the folded edges, so there is no seam.
#pragma once

#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

vec2 octahedralEncode(const vec3& direction);  // unit direction -> [0,1]^2
vec3 octahedralDecode(const vec2& uv);         // [0,1]^2 -> unit direction

class OctahedralMap {
 public:
  OctahedralMap() = default;
  explicit OctahedralMap(int size) : size_(size), texels_(std::size_t(size) * size, vec3(0.0f)) {}

  int size() const { return size_; }
  vec3& at(int x, int y) { return texels_[std::size_t(y) * size_ + x]; }
  const vec3& at(int x, int y) const { return texels_[std::size_t(y) * size_ + x]; }
  // Texel with octahedral wrapping for x, y one step outside [0, size).
  const vec3& wrapped(int x, int y) const;
  vec3 texelDirection(int x, int y) const;  // direction through the texel centre
  vec3 bilinear(const vec3& direction) const;
  // The same lookup at a direction already encoded (octahedralEncode): maps of every size share
  // the encoding, so a blend of two levels encodes its direction once.
  vec3 bilinearAt(const vec2& uv) const;
  // Half-resolution 2x2 box average (the next level of a MIP chain); size must be >= 2.
  OctahedralMap downsampled() const;

 private:
  int size_ = 0;
  std::vector<vec3> texels_;  // linear RGB, row-major
};

}  // namespace holo::reflect
