// The reflection framebuffer psi_r (paper Section 3.3): for every pixel of a face view, primary
// rays against the relic (Embree), each hit keeping position, shading normal, material and
// mirror-reflected direction, resolved by surface_shading.hpp with the pixel's footprint
// (1 / fx radians per pixel) for the texture filtering. A BLEND surface stops the primary ray
// (PartialHits::Solid): the static shading composites what is behind it. A pixel shades as the mean over its
// samples with misses black (the pyramid's background), so its silhouette coverage is the fraction of its
// samples that hit.
//
// Anti-aliasing, per pixel either one sample at the centre or four on a rotated grid (the fixed
// pattern keeps silhouettes stable from frame to frame):
//  * None: the centre only (aliased silhouettes);
//  * Edges: the centre everywhere, then the four sub-samples at pixels whose centre differs from
//    one of its 8 neighbours' (hit vs miss: the silhouette; normals more than ~18 degrees apart: a
//    crease; roughness or base colour apart: a material edge); such a pixel is the mean of its
//    four sub-samples, exactly as with Full. About 12% of the relic's pixels in the museum;
//  * Full: the four sub-samples at every pixel (4x the rays).
// Units: metres, world frame.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"

namespace holo::reflect {

struct HitPoint {
  vec3 position{0.0f};
  vec3 normal{0.0f, 1.0f, 0.0f};            // unit shading normal, on the viewer's side
  vec3 to_viewer{0.0f, 0.0f, 1.0f};         // wo, unit
  vec3 reflected{0.0f, 1.0f, 0.0f};         // mirror direction of wo about the normal, unit
  vec3 clearcoat_normal{0.0f, 1.0f, 0.0f};  // unit, viewer's side (surface_shading.hpp)
  SurfaceMaterial material;
  vec3 emission{0.0f};  // surface_shading.hpp's SurfacePoint fields
  float occlusion = 1.0f;
  float alpha = 1.0f;  // BLEND coverage: what is behind shows through 1 - alpha of it
  SurfaceLocation location;
  // The mirror ray (position, reflected) may meet the relic again (RenderScene::mayMeetRelicAgain):
  // false where the relic's shape proves it cannot, and the interreflection casts no ray there.
  bool mirror_may_meet_relic = true;
  // The relic's glTF material at the hit (transmission, volume, IOR, clearcoat: what the
  // refraction pass and the coat read), owned by the RenderScene; null only before tracing.
  const Material* gltf = nullptr;
};

enum class AntiAliasing { None, Edges, Full };
// "none" | "edges" | "full"; InputError naming `field` otherwise.
AntiAliasing parseAntiAliasing(const std::string& text, const std::string& field);
const char* antiAliasingName(AntiAliasing mode);

// Sub-sample offsets within a pixel (pixel centre = 0): 1 (the centre) or 4 (rotated grid).
std::vector<vec2> subsamplePattern(int samples);

struct HitPointBuffer {
  static constexpr std::uint32_t kCentreOnly = 0xffffffffu;
  int width = 0, height = 0;
  // hits[0, width * height): the pixel centres, row-major (all invalid with Full: not traced);
  // then four sub-samples per refined pixel, in the order of `refined`.
  std::vector<HitPoint> hits;
  std::vector<std::uint8_t> valid;       // 1 where the sample hit the relic, per entry of hits
  std::vector<std::uint32_t> refined;    // pixels (y * width + x) with four sub-samples, ascending
  std::vector<std::uint32_t> first_sub;  // per pixel: index in hits of its first sub-sample, or kCentreOnly
  // Pixels with at least one valid sample (coverage > 0), ascending: every other pixel is empty,
  // so passes over the relic's pixels need not visit the whole view.
  std::vector<std::uint32_t> covered;

  std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
  // Gives `per_sample` (an entry per entry of hits) room for as many entries as hits has room for,
  // so that a later trace with more samples, within what traceHitPoints reserved, moves neither.
  template <typename T>
  void reservePerSample(std::vector<T>& per_sample) const {
    if (per_sample.capacity() < hits.capacity()) per_sample.reserve(hits.capacity());
  }
  // The samples pixel p (= y * width + x) is the mean of: [firstSample(p), firstSample(p) + sampleCount(p)).
  std::size_t firstSample(std::size_t p) const { return first_sub[p] == kCentreOnly ? p : first_sub[p]; }
  int sampleCount(std::size_t p) const { return first_sub[p] == kCentreOnly ? 1 : 4; }
  float coverage(int x, int y) const;  // [0, 1]
};

// Traces the view into `out`, reusing its storage: it reserves a quarter more than the most the
// trace can hold (every traced pixel refined), so a later trace allocates only where the relic
// covers more of the view. With the relic's bounds (not empty) and a distortion-free view that
// has the whole box in front of it, only the pixels inside the box's projected rectangle are
// traced: the rest cannot hit the relic (a pinhole projects the box into the hull of its
// projected corners); with every relic vertex in front of the view too, each row is narrowed
// further to the projected bounding boxes of the relic's triangles on it. The result is the same
// as tracing every pixel.
void traceHitPoints(const RenderScene& scene, const CameraModel& view, AntiAliasing aa, HitPointBuffer& out,
                    const Bounds3& relic_bounds = {});

// One sample at image position `pixel` (pixel centres at integers), as traceHitPoints traces each:
// whether it hit the relic (`out` is written only then).
bool traceHitPoint(const RenderScene& scene, const CameraModel& view, const vec2& pixel, HitPoint& out);

}  // namespace holo::reflect
