// Prefiltered image-based lighting of a panorama (docs/architecture.md):
//  * specular: an octahedral map per roughness level. Level 0 (roughness 0) is the panorama
//    resampled by area averaging; levels 1.. hold roughness evenly spaced in sqrt(roughness)
//    from `min_roughness` to 1, each texel the exact integral of the GGX lobe with normal = view
//    = reflected direction (Karis' split-sum assumption) over the panorama's pixels
//    (lobe_integral.hpp: adaptive quadrature on a pyramid of the panorama; a sun is integrated
//    where it is, not smeared). A level of roughness r is max(48, ceil(texel_density / r))
//    texels wide, fine enough for bilinear lookups. Lookups blend the two levels around r
//    linearly in alpha = r^2.
//    Accuracy against brute force (tests/reflect/test_prefiltered_ibl.cpp, docs/reflect.md):
//    within 2% mean relative error for roughness 0.1..1 on the shared interior and hard-sun
//    panoramas.
//  * diffuse: irradiance from 9 spherical harmonics (irradiance_sh.hpp);
//  * the panorama's sun (panorama_sun.hpp), found when the maps are built, and the diffuse light
//    without it, for a renderer that lights the relic with the sun as a directional light;
//  * the split-sum DFG table (dfg_table.hpp) for the specular scale and bias.
// Units: radiance in, radiance out. Build cost is measured in tests/reflect/bench_reflect.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "holo/reflect/octahedral_map.hpp"
#include "holo/reflect/panorama_sun.hpp"

namespace holo::reflect {

struct PrefilterOptions {
  int levels = 10;             // roughness levels including the mirror, >= 2
  int base_size = 0;           // octahedral size of level 0; 0 = from the panorama width
  int texel_density = 20;      // a level of roughness r is max(48, ceil(texel_density / r)) wide
  float min_roughness = 0.1f;  // roughness of level 1 (below it lookups blend with the mirror)
  float tail_ratio = 1.5f;     // LobeQuadratureOptions::tail_ratio (accuracy against time)
  SunSearchSettings sun{};     // how the panorama's sun is found
};

// The split-sum shading in parts, so a renderer can put the foreground's radiance in place of
// the environment's in the specular part: radiance = specular_scale * L + diffuse, with
// L = environment for the static hall alone.
struct SplitSumShading {
  vec3 specular_scale{0.0f};  // F0 * A + F90 * B (DFG table), in [0, 1]
  vec3 diffuse{0.0f};         // SH irradiance diffuse, radiance
  vec3 environment{0.0f};     // prefiltered environment radiance along `reflected`
};

class PrefilteredIbl {
 public:
  PrefilteredIbl() = default;
  explicit PrefilteredIbl(const Environment& environment, PrefilterOptions options = {});

  // Prefiltered radiance around `direction` (the hall's frame) for a GGX lobe of this perceptual
  // roughness, seen from the panorama's capture point.
  vec3 specular(const vec3& direction, float roughness) const;
  // Radiance of the hall a ray on the relic from `origin` along `direction` meets, through the
  // proxy (parallax) and at perceptual `roughness`.
  vec3 seenFrom(const vec3& origin, const vec3& direction, float roughness) const {
    return specular(proxy_.lookupDirection(turnPoint(origin), turnDirection(direction)), roughness);
  }
  vec3 irradiance(const vec3& normal) const { return sh_.irradiance(turnDirection(normal)); }
  // The diffuse light's radiance coefficients (irradiance_sh.hpp) in the relic's frame: those of
  // the hall's, turned with the relic (setRelicTurn).
  std::array<vec3, 9> relicFrameRadiance() const { return sh_.turnedAboutY(turn_cos_, turn_sin_); }
  // The panorama's sun (found or not; its direction in the hall's frame).
  const PanoramaSun& sun() const { return sun_; }
  // Towards the sun in the relic's frame (unit; the hall's turned back with the relic).
  vec3 relicFrameSunDirection() const {
    const vec3& d = sun_.direction;
    return turn_angle_ == 0.0f
               ? d
               : vec3(turn_cos_ * d.x - turn_sin_ * d.z, d.y, turn_sin_ * d.x + turn_cos_ * d.z);
  }
  // The sun's radiance coefficients (PanoramaSun::radiance_sh) in the relic's frame.
  std::array<vec3, 9> relicFrameSunRadiance() const {
    return IrradianceSH(sun_.radiance_sh).turnedAboutY(turn_cos_, turn_sin_);
  }
  // irradiance() without the sun's excess (all of it when no sun was found).
  vec3 irradianceWithoutSun(const vec3& normal) const {
    return sunless_sh_.irradiance(turnDirection(normal));
  }
  // The sun's part of seenFrom(origin, direction, roughness), the sun taken as a point
  // (PanoramaSun::lobe); zero without a sun.
  vec3 sunSeenFrom(const vec3& origin, const vec3& direction, float roughness) const {
    if (!sun_.found) return vec3(0.0f);
    return sun_.lobe(proxy_.lookupDirection(turnPoint(origin), turnDirection(direction)), roughness);
  }
  // Radiance leaving a surface at `position` (world, metres) towards `wo` (split-sum specular +
  // SH diffuse). The specular lookup goes through the environment's PanoramaProxy: the lobe's
  // centre direction from `position` is turned into the panorama direction it meets (parallax
  // correction of the lookup; the lobe's width stays the one prefiltered at the capture point).
  vec3 shade(const SurfaceMaterial& material, const vec3& normal, const vec3& wo, const vec3& position) const;
  // shade() in parts; `reflected` is wo mirrored about the normal. All zero when wo is not in
  // front of the surface. `irradiance`, when given, is the diffuse part's irradiance in place of
  // the unoccluded irradiance(normal) (the relic's visibility, relic_visibility.hpp).
  SplitSumShading shadeParts(const SurfaceMaterial& material, const vec3& normal, const vec3& wo,
                             const vec3& reflected, const vec3& position,
                             const vec3* irradiance = nullptr) const;
  const PanoramaProxy& proxy() const { return proxy_; }

  // A turntable: the relic turned by `angle_rad` (counter-clockwise seen from above) about the
  // vertical line through `pivot`, while its ray scenes keep the unturned relic. From then on
  // every lookup of a point or direction on the relic (seenFrom, irradiance, shade, shadeParts)
  // takes it in the unturned relic's frame and turns it into the hall's, so the renderer traces
  // the still relic in a hall turned the other way: the same picture as the turned relic in the
  // hall (the caller turns the eyes and the visitors likewise). 0 (the default) costs nothing.
  // Set between frames, never while a renderer reads the IBL.
  void setRelicTurn(const vec3& pivot, float angle_rad);
  float relicTurn() const { return turn_angle_; }

  int levelCount() const { return static_cast<int>(levels_.size()); }
  float levelRoughness(int level) const { return level_roughness_.at(static_cast<std::size_t>(level)); }
  const OctahedralMap& level(int l) const { return levels_.at(static_cast<std::size_t>(l)); }
  std::uint64_t sourceHash() const { return source_hash_; }
  bool empty() const { return levels_.empty(); }
  // The largest radiance, per channel, of any level's texel: no lookup (specular, seenFrom, blends
  // of levels) returns more. What the effect plan bounds a displayed change with.
  vec3 brightest() const { return brightest_; }

 private:
  std::vector<OctahedralMap> levels_;
  std::vector<float> level_roughness_;
  IrradianceSH sh_;
  PanoramaSun sun_;
  IrradianceSH sunless_sh_;
  vec3 turnPoint(const vec3& p) const {
    return turn_angle_ == 0.0f ? p : turn_pivot_ + turnDirection(p - turn_pivot_);
  }
  vec3 turnDirection(const vec3& d) const {
    return turn_angle_ == 0.0f
               ? d
               : vec3(turn_cos_ * d.x + turn_sin_ * d.z, d.y, turn_cos_ * d.z - turn_sin_ * d.x);
  }

  PanoramaProxy proxy_;
  vec3 brightest_{0.0f};
  std::uint64_t source_hash_ = 0;
  float turn_angle_ = 0.0f, turn_cos_ = 1.0f, turn_sin_ = 0.0f;
  vec3 turn_pivot_{0.0f};
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
