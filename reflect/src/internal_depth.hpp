// The internal-depth probe (internal): how many interface events the relic's transmitted light
// needs (EffectPlan::internal_depth where TracerSettings::refraction_depth is 0, "measured").
// Probe rays from a sphere of directions around the relic are traced through it (glass
// transport, glass_transport.hpp) with a cap of kMaxInternalDepth, keeping the share of the
// transmitted light still being followed after k events, per RGB channel; the depth is the
// smallest k whose largest channel share is below TracerSettings::refraction_residual.
#pragma once

#include <cstdint>
#include <vector>

#include "glass_transport.hpp"
#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/frame_result.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

struct InternalDepth {
  int depth = 1;
  float residual = 0.0f;         // share of the transmitted light still inside at that depth
  std::vector<double> left;      // the share after k = 0..kMaxInternalDepth events (the largest
                                 // over the RGB channels)
  std::uint32_t probes_hit = 0;  // probe rays that met a transmissive material
};
// The smallest depth whose residual is below `residual_limit` (kMaxInternalDepth when none is),
// from a fixed set of probe rays (deterministic). A relic without transmission: depth 1, 0 left.
InternalDepth measureInternalDepth(const RenderScene& scene, const PrefilteredIbl& ibl,
                                   const TracerSettings& settings, float residual_limit);

}  // namespace holo::reflect
