// Triangle meshes in an Embree 3 scene, for rays. One Embree device per process with one error
// callback (errors are logged and counted under "Embree/Errors"). Meshes are copied in, so the
// caller's meshes may go away. Thread-safe for queries after commit(); not for edits.
#pragma once

#include <embree3/rtcore.h>
#include <cstdint>
#include <deque>
#include <functional>
#include <span>

#include "holo/core/mesh.hpp"

namespace holo {

struct RayHit {
  float t = 0;                                       // distance along the (unit) ray direction
  std::uint32_t geometry = RTC_INVALID_GEOMETRY_ID;  // id returned by addMesh
  std::uint32_t primitive = 0;
  vec2 barycentric{0};       // Embree's (u, v): p = (1-u-v) p0 + u p1 + v p2
  vec3 geometric_normal{0};  // unit, facing against the ray
  bool hit() const { return geometry != RTC_INVALID_GEOMETRY_ID; }
};

// How a candidate hit's opacity (RayScene::setHitOpacity) decides whether the ray stops there.
// Opacity 0 always passes and 1 always stops; between them:
//  * Stochastic: the ray stops with probability = opacity, drawn from a hash of the ray and the
//    hit (deterministic; rays that differ in origin or direction draw independently), so a Monte
//    Carlo estimator averages to the surface composited over what is behind it;
//  * Solid: the ray stops (the caller composites what is behind itself).
enum class PartialHits { Stochastic, Solid };

// What a batch of rays cast together is like (Embree's intersect-context flags): Coherent for rays
// with nearby origins and directions that traverse the scene alike (a view's primary rays over a
// tile), traced as packets; Incoherent for rays that scatter (reflections off a curved surface),
// which Embree traces one ray at a time inside the packet.
enum class RayCoherence { Coherent, Incoherent };

// A geometry's opacity at a candidate hit, in [0, 1] (e.g. a cut-out texel reads 0).
using HitOpacity = std::function<float(const Ray& ray, const RayHit& hit)>;

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Adds a copy of the mesh and returns its geometry id (0, 1, 2, ... in call order).
  std::uint32_t addMesh(const TriangleMesh& mesh);
  // Replaces the vertex positions of a mesh (same count); call commit() afterwards.
  void updatePositions(std::uint32_t geometry, const std::vector<vec3>& positions);
  // Makes every ray query (intersect and occluded) ask `opacity` about each candidate hit on the
  // geometry (Embree's filter functions); call before commit(). Geometries without one are opaque.
  void setHitOpacity(std::uint32_t geometry, HitOpacity opacity);
  void commit();

  RayHit intersect(const Ray& ray, float tmin = 0.0f, float tmax = 1e30f,
                   PartialHits partial = PartialHits::Stochastic) const;
  bool occluded(const Ray& ray, float tmin = 0.0f, float tmax = 1e30f) const;  // Stochastic
  // hits[i] = intersect(rays[i], tmin, tmax, partial) for every i (rays.size() == hits.size()),
  // cast packetWidth() at a time as packets (Embree's rtcIntersect8 or rtcIntersect16) with
  // `coherence`'s flag. The same hit as one ray at a time, bit for bit in t and the barycentrics
  // up to Embree's packet kernels' round-off (a few ulps).
  void intersectPackets(std::span<const Ray> rays, std::span<RayHit> hits, RayCoherence coherence,
                        float tmin = 0.0f, float tmax = 1e30f,
                        PartialHits partial = PartialHits::Stochastic) const;
  // intersectPackets of coherent rays: for a view's primary rays over a tile, the fastest way
  // Embree 3 casts them.
  void intersectCoherent(std::span<const Ray> rays, std::span<RayHit> hits, float tmin = 0.0f,
                         float tmax = 1e30f, PartialHits partial = PartialHits::Stochastic) const {
    intersectPackets(rays, hits, RayCoherence::Coherent, tmin, tmax, partial);
  }
  // Rays per packet: 8 or 16. A new scene takes nativePacketWidth(); setPacketWidth (an edit:
  // not while queries run) casts the same hits in packets of the other width.
  int packetWidth() const { return packet_width_; }
  void setPacketWidth(int width);  // throws holo::Error unless width is 8 or 16
  // The widest packet Embree's kernels on this CPU cast natively: 16 with AVX-512, where a view's
  // coherent primary rays take less CPU in 16s than in 8s (docs/frame_loop.md, "Embree packet
  // tracing"); else 8, since without 16-wide kernels Embree splits a packet of 16 itself.
  static int nativePacketWidth();

  const TriangleMesh& mesh(std::uint32_t geometry) const { return meshes_.at(geometry); }
  std::size_t meshCount() const { return meshes_.size(); }
  // Interpolated unit shading normal at a hit (geometric normal when the mesh has none), turned
  // to the side the ray came from.
  vec3 shadingNormal(const RayHit& hit, const vec3& ray_direction) const;
  vec2 uv(const RayHit& hit) const;  // (0,0) when the mesh has no uvs
  vec3 position(const Ray& ray, const RayHit& hit) const { return ray.origin + hit.t * ray.direction; }

 private:
  RTCScene scene_ = nullptr;
  std::deque<TriangleMesh> meshes_;  // deque: stable addresses for Embree's shared buffers
  std::vector<RTCGeometry> geometries_;
  std::deque<HitOpacity> opacities_;  // deque: stable addresses for Embree's user data
  int packet_width_ = nativePacketWidth();
};

RTCDevice embreeDevice();

}  // namespace holo
