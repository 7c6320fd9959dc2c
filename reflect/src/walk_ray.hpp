// What the frame renderer's static pass hands its foreground walk (internal): per hit point the
// ray whose foreground it shows, and whether its material reads the rough map instead of walking.
#pragma once

#include "holo/core/math.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

// Whether a material of this roughness takes its foreground from the rough map (null: none).
inline bool readsRoughMap(const RoughForegroundMap* map, const TracerSettings& settings, float roughness) {
  return map != nullptr && roughness >= settings.foreground_map_roughness;
}

// The ray a hit point's foreground walk follows: its mirror ray, or the mirror ray of its
// interreflection's second point (bounced), with the two lobes' roughness combined.
struct WalkRay {
  vec3 position{0.0f}, normal{0.0f, 1.0f, 0.0f}, reflected{0.0f, 1.0f, 0.0f};
  float roughness = 0.0f;
  bool bounced = false;
};

}  // namespace holo::reflect
