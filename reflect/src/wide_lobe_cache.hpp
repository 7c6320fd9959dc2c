// The rough interreflection of the widest lobes in object space (internal): for a relic material at
// least kGlossyRoughnessLimit rough (effect_plan.hpp) and not textured, the lobe's sums
// (lobe_bounce.hpp: its strata's hall, open share and the second points' shading) are a smooth
// function of the surface point and of the direction to the eye, and depend on the relic and the
// hall's light only. So they are kept per vertex side and per bin of the eye's direction in the
// vertex's frame (a bins x bins grid over the hemi-octahedral square of the hemisphere), each entry
// all side^2 strata at their centres traced from the vertex, computed the first time a hit point
// needs it and then shared by every view and frame until the light changes (clear()). A hit point
// reads its triangle's three vertices' entries, each bilinear over the four bins around its eye
// direction, weighted by its barycentric coordinates: no per-pixel noise, so nothing to pool,
// filter or refine. A moving eye, whose view's static shading is redone every frame, then costs a
// lookup per sample instead of its strata's rays.
// Deterministic: an entry's value depends on its vertex and bin alone, whichever thread computes it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "holo/core/mesh.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "lobe_bounce.hpp"

namespace holo::reflect {

class WideLobeCache {
 public:
  // The lobe sums of the strata traced from `position` (a vertex, unit `normal` the side's) for
  // the eye in unit direction `to_viewer`, with the material of that vertex's mesh.
  using Trace = std::function<LobeBounce(const vec3& position, const vec3& normal, const vec3& to_viewer)>;

  // Entries for every vertex side of the relic's meshes whose material (or the scene's override)
  // is at least kGlossyRoughnessLimit rough and has no metallic-roughness texture; `bins` per side
  // of the direction grid, 2..16 (throws InputError otherwise).
  WideLobeCache(const RenderScene& scene, int bins);
  ~WideLobeCache();

  // Whether `at` (a located relic point) reads its lobe from the cache.
  bool covers(const SurfaceLocation& at) const;
  // Whether the front of relic mesh `mesh` does.
  bool coversMesh(std::size_t mesh) const { return mesh < covered_.size() && covered_[mesh]; }
  // The lobe sums at `at` (covers(at)) for the eye in direction `to_viewer`, computing the entries
  // it reads that are not yet kept with `trace`.
  LobeBounce lookup(const SurfaceLocation& at, const vec3& to_viewer, const Trace& trace) const;
  // Forgets every entry (the light or the plan changed).
  void clear();
  // Whether some mesh is covered.
  bool active() const { return active_; }
  // Entries computed since construction (each once, unless two threads met on it).
  std::uint64_t computed() const { return computed_.load(); }

 private:
  struct Entry {
    std::atomic<std::uint8_t> state{0};  // 0 empty, 1 being computed, 2 ready
    LobeBounce value;
  };
  // The eye direction of bin (i, j) in the local frame (z up).
  vec3 binDirection(int i, int j) const;
  const LobeBounce& entry(std::size_t mesh, int side, std::uint32_t vertex, int bin, const Frame& frame,
                          const Trace& trace, LobeBounce& scratch) const;

  const Model& relic_;
  int bins_;
  bool active_ = false;
  std::vector<std::uint8_t> covered_;  // per mesh
  // Per mesh and side, each vertex's frame about the side's unit normal (none: a zero normal).
  std::vector<std::array<std::vector<std::optional<Frame>>, 2>> frames_;
  // Per mesh and side (0 front, 1 back): vertices x bins^2 entries (empty where not covered).
  std::vector<std::array<std::unique_ptr<Entry[]>, 2>> entries_;
  mutable std::atomic<std::uint64_t> computed_{0};
};

}  // namespace holo::reflect
