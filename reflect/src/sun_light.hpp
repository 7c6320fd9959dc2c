// The panorama's sun (panorama_sun.hpp) as a directional light on the relic's diffuse surfaces
// (internal, for the static shading): its excess irradiance times the exact clamped cosine of the
// shading normal, times what the relic passes along the way to the sun (relic_passage.hpp: one
// shadow ray, continued through glass, which tints it as the glass shading does). The diffuse
// light it goes with is the panorama's without the sun (PrefilteredIbl::irradianceWithoutSun, or
// the relic's visibility lit without it), so the sun is counted once.
#pragma once

#include <cstdint>

#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

class SunLight {
 public:
  // `scene`, `ibl` and `settings` must outlive this. The sun is the ibl's (in the relic's frame).
  SunLight(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings);
  // The sun's irradiance (RGB) at a relic point seen from `to_viewer` (unit): no ray where its
  // shading normal or its triangle's face (on the viewer's side) turns away from the sun. `rays`
  // counts the shadow rays' Embree rays.
  vec3 irradiance(const SurfacePoint& surface, const vec3& to_viewer, std::uint32_t& rays) const;

 private:
  const RenderScene& scene_;
  const TracerSettings& settings_;
  vec3 direction_;
  vec3 power_;
};

// Whether a surface reads the sun's irradiance (and so shows its shadow): a part with a diffuse
// base colour; an all-metal or all-glass part reads only its specular terms.
inline bool readsSunIrradiance(const SurfaceMaterial& m) {
  return (1.0f - m.metallic) * (1.0f - m.transmission) > 0.0f && maxComponent(m.base_colour) > 0.0f;
}

}  // namespace holo::reflect
