// The virtual plinth's light and its drawing in a view (internal to the frame renderer). The top
// face's irradiance is a map over its square: the hall's unshadowed irradiance (the IBL's
// spherical harmonics) less the light the relic blocks, plus the caustic the relic focuses onto
// it (caustic_tracer.hpp). The blocked light is the delta of the relic alone: per texel, rays
// against the relic, half cosine-distributed over strata and half drawn from the hall's bright
// directions (environment_directions.hpp), the hall's radiance times cosine along those that meet
// it summed by the balance heuristic, so a texel the relic does not shadow is exact and a small
// lamp's shadow is sharp. Glass blocks like any surface here;
// the light it lets through is the caustic's. The sides take the unshadowed irradiance. The
// plinth is Lambertian: radiance albedo / pi times irradiance. Units: metres, linear radiance.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/core/plinth.hpp"
#include "holo/reflect/caustic_tracer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

class PlinthLight {
 public:
  // resolution: texels along the top's side; shadow_rays: per texel (rounded to twice a square).
  PlinthLight(const PlinthBox& box, int resolution, int shadow_rays);
  // Lights the top under `ibl` (its panorama and relic turn) with the relic's shadow, and adds
  // `caustic` (null: none) over its square; without `shadow` the top is unshadowed. Returns the
  // shadow rays cast.
  std::uint64_t light(const RenderScene& scene, const PrefilteredIbl& ibl, const CausticImage* caustic,
                      bool shadow = true);
  // Irradiance (RGB, W/m^2-like units of the IBL) at a point of the box's face with outward `normal`.
  vec3 irradiance(const vec3& position, const vec3& normal, const PrefilteredIbl& ibl) const;
  const PlinthBox& box() const { return box_; }
  // The caustic's irradiance map in use (empty: none), and its receiver grid.
  const CausticImage& caustic() const { return caustic_; }

 private:
  PlinthBox box_;
  int resolution_;
  int shadow_rays_;
  std::vector<vec3> blocked_;  // per texel (row = z, column = x), RGB
  vec3 unshadowed_top_{0.0f};
  CausticImage caustic_;
};

// Where the plinth is seen in `view` (four sub-samples a pixel), its radiance over the relic's
// static image `hdr` (BGR): behind the relic's covered share, in front of the relic where it is
// nearer. Appends the pixels it touched (ascending) to `pixels`.
void drawPlinth(const PlinthLight& light, const PrefilteredIbl& ibl, const CameraModel& view,
                const HitPointBuffer& hits, cv::Mat& hdr, std::vector<std::uint32_t>& pixels);

}  // namespace holo::reflect
