// The reflection framebuffer psi_r (paper Section 3.3): for every pixel of a face view, up to
// `samples` sub-pixel primary rays against the relic (Embree), each hit keeping position, shading
// normal, material and mirror-reflected direction. A pixel's silhouette coverage is the fraction
// of its sub-samples that hit; pixels shade as the mean over sub-samples with misses black (the
// pyramid background), so silhouettes are anti-aliased and stable from frame to frame (the
// sub-sample pattern is fixed). Units: metres, world frame.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

struct HitPoint {
  vec3 position{0.0f};
  vec3 normal{0.0f, 1.0f, 0.0f};     // unit shading normal, on the viewer's side
  vec3 to_viewer{0.0f, 0.0f, 1.0f};  // wo, unit
  vec3 reflected{0.0f, 1.0f, 0.0f};  // mirror direction of wo about the normal, unit
  SurfaceMaterial material;
};

// Sub-sample offsets within a pixel (pixel centre = 0): 1 (the centre) or 4 (rotated grid).
std::vector<vec2> subsamplePattern(int samples);

struct HitPointBuffer {
  int width = 0, height = 0, samples = 1;
  std::vector<HitPoint> hits;       // width * height * samples, row-major, sub-sample fastest
  std::vector<std::uint8_t> valid;  // 1 where the sub-sample hit the relic
  std::size_t index(int x, int y, int s) const {
    return (std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(samples) + std::size_t(s);
  }
  float coverage(int x, int y) const;  // [0, 1]
};

// samples must be 1 or 4 (InputError otherwise).
HitPointBuffer traceHitPoints(const RenderScene& scene, const CameraModel& view, int samples);

}  // namespace holo::reflect
