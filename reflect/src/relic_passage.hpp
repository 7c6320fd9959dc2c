// What the relic passes of light travelling straight through it (internal): a shadow ray's path,
// not bent. Each entry into a transmissive material passes (1 - F)(1 - metallic) transmission
// base_colour of the light and each exit from a volume 1 - F (as the path tracer's glass: tinted
// where the light enters), each volume segment its Beer-Lambert share; an opaque part stops it.
// Used by what stands inside the glass (inside_glass.hpp), the sun's shadow (sun_light.hpp) and
// the light a later glass wall reflects back along its own mirror direction (glass_transport.hpp).
#pragma once

#include <cstdint>

#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

// What a glass interface takes from the light: its Fresnel reflection (light along one direction:
// the sun's, a mirror direction's), or nothing (light gathered over a wide lobe: a wall reflects
// into the lobe, from its mirror direction, about as much as it reflects out of it, so an even hall
// seen through a lossless glass case is as bright inside it as outside; tint and absorption stay).
enum class InterfaceLoss { Fresnel, None };

// RGB in [0, 1] of the light arriving at `origin` from unit `direction`; `rays` counts the
// Embree rays (at most kMaxRelicCrossings).
vec3 passedThroughRelic(const RenderScene& scene, const TracerSettings& settings, const vec3& origin,
                        const vec3& direction, std::uint32_t& rays,
                        InterfaceLoss loss = InterfaceLoss::Fresnel);

// Interfaces a light ray crosses before it is counted as stopped (glass walls come in pairs).
inline constexpr int kMaxRelicCrossings = 8;

}  // namespace holo::reflect
