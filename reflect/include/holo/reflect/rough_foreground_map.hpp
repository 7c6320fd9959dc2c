// The visitors as seen from the relic's centre, prefiltered with a wide GGX lobe: the foreground
// term for lobes too wide for the voxel walk. At roughness ~0.6 one walked ray reads a blur
// around one point of one camera's image, while the lobe spans tens of degrees over several
// visitors and the hall between them: edges come out hard and the colour of whichever camera saw
// the hit (docs/tracer/voxel_walk.md, "Rough relics"). The paper's IBL integrates the lobe exactly over the
// visitors reprojected around the relic; this does the same per frame for the visitors alone, at
// a resolution a frame can afford.
//
// Per frame: every occupied voxel of the grid is splatted into a small equirectangular map
// around `centre` as a disc of one voxel edge's angular radius, the nearest voxel winning each
// texel (premultiplied radiance * weight, and the coverage weight); then, for each roughness
// asked for, the map is integrated against the GGX lobe around every texel's direction
// (W(l) = D(h) n.l with normal = view = the texel's direction, as
// lobe_integral.hpp) over the covered texels only; the normalisation over the whole sphere depends
// on the map's geometry alone and is computed once. lookup() reads the prefiltered maps bilinearly
// (wrapping in longitude) at the nearest prefiltered roughness: radiance = C / w, weight = w.
// Parallax is ignored, as in the paper's IBL: directions are taken from the centre.
// Units: metres, linear radiance, radians; directions need not be unit length.
#pragma once

#include <vector>

#include "holo/core/math.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

class RoughForegroundMap {
 public:
  // width x width / 2 texels (width even, >= 8; throws InputError otherwise); roughness values
  // in (0, 1] to prefilter for (others are clamped into it), at most 8.
  RoughForegroundMap(int width, std::vector<float> roughness);

  // Rebuilds from this frame's grid (empty grid: every lookup has weight 0).
  void build(const VoxelGrid& grid, const vec3& centre);
  // The prefiltered foreground in `direction` for the prefiltered roughness nearest to
  // `roughness`; weight 0 for a zero or non-finite direction.
  ForegroundSample lookup(const vec3& direction, float roughness) const;

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<float>& roughness() const { return roughness_; }
  std::size_t coveredTexels() const { return covered_.size(); }

 private:
  struct Texel {
    vec3 premultiplied{0.0f};
    float weight = 0.0f;
  };
  int width_ = 0, height_ = 0;
  std::vector<float> roughness_;
  std::vector<float> k1_;                     // per roughness, ggxLobeK1 of its alpha
  std::vector<vec3> direction_;               // per texel, unit, its centre
  std::vector<float> solid_angle_;            // per texel, sr
  std::vector<std::vector<float>> norm_;      // per roughness, per texel: sum of W over the sphere
  std::vector<Texel> splat_;                  // this frame's map
  std::vector<float> depth_;                  // per texel, nearest splatted distance
  std::vector<std::uint32_t> covered_;        // texels with weight > 0
  std::vector<std::vector<Texel>> filtered_;  // per roughness
};

}  // namespace holo::reflect
