// The caustic a transmissive relic casts on the real receiver under it, for the AR composite: the
// panorama's light that the relic's glass focuses onto the pyramid base's top (the horizontal
// plane y = receiver_height of the world frame), traced by the appliance's light tracer
// (reflect/caustic_tracer.hpp) with its photons drawn as the composite's path tracer samples the
// panorama (reflect::Environment::sample), so both see the same light.
//
// The composite (local_path_tracing.hpp) adds it as the relic's added light at a real surface
// point on the receiver, radiance albedo / pi times the caustic's irradiance there, and there
// leaves out the same light paths from its BSDF sampling (a sampled direction that crosses only
// the relic's glass before it reaches the panorama): the light tracer finds a small lamp through
// the glass that BSDF sampling almost never does.
//
// The plan: traced only for a relic with a transmissive material whose lowest point is at or
// above the receiver (RelicCausticSettings::kStandingTolerance below it at most: a relic standing
// on the base); otherwise nothing is traced (the counters `Caustics/Live photons traced` stay 0).
// Units: metres, world (pyramid) frame, +Y up; irradiance W/m^2 per unit panorama radiance.
#pragma once

#include <cstdint>
#include <optional>

#include "holo/core/camera_model.hpp"
#include "holo/core/math.hpp"
#include "holo/core/mesh.hpp"
#include "holo/reflect/caustic_tracer.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::ar {

struct RelicCausticSettings {
  bool enabled = true;
  float receiver_height = 0.0f;  // y of the receiver's plane: the pyramid base's top
  // The receiver's grid: a square centred under the relic, its half side in the relic's bounding
  // radii (a low lamp throws the caustic beside the relic), `resolution` cells a side.
  float half_size_radii = 3.0f;
  int resolution = 128;
  std::uint64_t photons = 1u << 18;
  std::uint64_t seed = 1;
  // A real surface point is on the receiver within this height of its plane (the depth surface's
  // noise) and with its normal this close to up (cosine).
  float receiver_tolerance = 0.01f;
  float receiver_min_cos = 0.7f;

  static constexpr float kStandingTolerance = 1e-3f;  // metres a relic's foot may sink below
};

class RelicCaustic {
 public:
  explicit RelicCaustic(reflect::CausticImage image, float tolerance, float min_cos)
      : image_(std::move(image)), tolerance_(tolerance), min_cos_(min_cos) {}

  // Whether a real surface point p with its normal n (unit, facing the viewer) lies on the
  // receiver, lit from above.
  bool onReceiver(const vec3& p, const vec3& n) const;
  // The caustic's irradiance at p (RGB; bilinear over the grid's cells; 0 beyond it).
  vec3 irradianceAt(const vec3& p) const;
  const reflect::CausticImage& image() const { return image_; }

 private:
  reflect::CausticImage image_;
  float tolerance_;
  float min_cos_;
};

// Adds to `region` (CV_8UC1 of the camera's size, change_region.hpp; 255 = traced) the pixels
// the caustic may change: every grid cell whose light, on a white receiver (albedo 1), moves the
// background's displayed code at the cell's centre by at least `negligible_codes` marks the
// pixels its projected square covers, dilated by one. An empty region (every pixel traced) is
// left as it is.
void addCausticToRegion(const RelicCaustic& caustic, const CameraModel& camera, const cv::Mat& background,
                        float negligible_codes, float exposure, cv::Mat& region);

// nullopt, tracing nothing, unless `settings.enabled`, the relic transmits and stands on or above
// the receiver.
std::optional<RelicCaustic> traceRelicCaustic(const Model& relic, const reflect::Environment& environment,
                                              const RelicCausticSettings& settings);

}  // namespace holo::ar
