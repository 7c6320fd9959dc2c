// Prefiltered image-based lighting of a panorama (DESIGN.md step 4, the FIS paper):
//  * specular: an octahedral map per roughness level, level l holding roughness
//    l / (levels - 1) (linear in perceptual roughness; lookups interpolate linearly between the
//    two nearest levels). Level 0 (roughness 0) is the panorama resampled by area averaging;
//    level l > 0 is the GGX lobe with normal = view = reflected direction (Karis' split-sum
//    assumption), estimated per texel by filtered importance sampling (Krivanek & Colbert 2008):
//    K GGX-distributed samples, each read from the source MIP chain at
//        lod = max(0, 0.5 * log2(Omega_s / Omega_p) + 1),  Omega_s = 1 / (K pdf),
//        Omega_p = 4 pi / size0^2 (one base texel),
//    weighted by n.l. Level resolution follows the lobe width (finer for sharper levels).
//    The panorama's brightest pixels (luminance > 32 x the mean, at most 256: a sun, a lamp)
//    are taken out of the FIS source and integrated exactly for every texel, so a hard sun is
//    neither missed nor smeared across the horizon by a blurred MIP level.
//  * diffuse: irradiance from 9 spherical harmonics (irradiance_sh.hpp);
//  * the split-sum DFG table (dfg_table.hpp) for the specular scale and bias.
// Units: radiance in, radiance out. Build cost is measured in tests/reflect/bench_reflect.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "holo/reflect/octahedral_map.hpp"

namespace holo::reflect {

struct PrefilterOptions {
  int levels = 9;              // roughness levels, >= 2
  int base_size = 0;           // octahedral size of level 0; 0 = from the panorama width
  int samples_per_texel = 64;  // K of the FIS estimate
  float lod_bias = 0.0f;       // added to the FIS level (Krivanek & Colbert use 1; 0 measured better)
};

class PrefilteredIbl {
 public:
  PrefilteredIbl() = default;
  explicit PrefilteredIbl(const Environment& environment, PrefilterOptions options = {});

  // Prefiltered radiance around `direction` for a GGX lobe of this perceptual roughness.
  vec3 specular(const vec3& direction, float roughness) const;
  vec3 irradiance(const vec3& normal) const { return sh_.irradiance(normal); }
  // Radiance leaving a surface towards `wo` (split-sum specular + SH diffuse).
  vec3 shade(const SurfaceMaterial& material, const vec3& normal, const vec3& wo) const;

  int levelCount() const { return static_cast<int>(levels_.size()); }
  float levelRoughness(int level) const;
  const OctahedralMap& level(int l) const { return levels_.at(static_cast<std::size_t>(l)); }
  std::uint64_t sourceHash() const { return source_hash_; }
  bool empty() const { return levels_.empty(); }

 private:
  std::vector<OctahedralMap> levels_;
  IrradianceSH sh_;
  std::uint64_t source_hash_ = 0;
};

// Keeps a PrefilteredIbl in step with a panorama that may change: get() rebuilds only when the
// environment's content hash differs from the one the current maps were built from.
class IblCache {
 public:
  explicit IblCache(PrefilterOptions options = {}) : options_(options) {}
  const PrefilteredIbl& get(const Environment& environment);
  int builds() const { return builds_; }

 private:
  PrefilterOptions options_;
  PrefilteredIbl ibl_;
  int builds_ = 0;
};

}  // namespace holo::reflect
