// Sparse anchors (internal): the refraction pass's reconstruction of the transmitted paths from a
// sparse lattice of traced ones (TracerSettings::refraction_stride s > 1).
//
// Paths are traced only at anchors, the pixel centres (x, y) with x and y multiples of s, and every
// other sample takes the bilinear blend of the anchors around it where all of them are on the same
// smooth piece of the relic as the sample (same material, normals within ~25 degrees, the anchor
// near the sample's tangent plane) and agree on what the light does inside (the same events, all
// exited or all capped, exit directions within ~8 degrees); elsewhere (silhouettes, creases, the
// rim, where the exit direction turns fast) the sample traces its own path. What is blended is the
// path per unit of light entering, times the sample's own entry weight (its exact Fresnel and
// tint), so a blend keeps the white furnace; the exit ray's IBL is read along the blended
// direction. The anchors off the coarse lattice (every second anchor each way) blend the coarse
// anchors likewise (exit directions within ~2 degrees) and trace where these disagree. The
// visitors seen through the glass are walked along the traced paths' exit rays; a blended sample
// or anchor takes the blend of its anchors' walks where these see the same, and walks its own exit
// ray elsewhere.
#pragma once

#include <cstdint>
#include <vector>

#include "foreground_walk.hpp"
#include "glass_transport.hpp"
#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/frame_result.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

// Where a sample's visitors seen through the relic come from: the walk of its own exit ray
// (anchors == 0, shared < 0 and supersampled < 0), of the pixel's sub-sample whose path it shares
// (shared, a sample index), the blend of the walks of the anchors its path blended, with the same
// weights, or the walks of its supersampled paths (supersampled, an index into
// LayerBuffers::supersampled, refraction_pass.hpp).
struct WalkSource {
  std::uint32_t anchor[4] = {};  // indices into the anchor grid (LayerBuffers::anchors)
  float weight[4] = {};          // sum to 1
  std::uint8_t anchors = 0;
  std::int32_t shared = -1;
  std::int32_t supersampled = -1;
};

// A traced path at an anchor pixel, per unit of light entering.
struct RefractionAnchor {
  vec3 position{0.0f}, normal{0.0f, 1.0f, 0.0f};
  const Material* material = nullptr;  // null: no anchor there
  TransmittedPath unit;                // scale, resolved and reflected per unit entry weight
  WalkSource source;                   // the coarse anchors it blended (their indices), if it did
};

// The lattice of anchors over a view's hit points, row-major.
struct AnchorGrid {
  int stride = 1;  // pixels between anchors; 1: every sample traces its own path, no anchors
  int width = 0, height = 0;
  std::size_t size() const { return std::size_t(width) * std::size_t(height); }
};
AnchorGrid anchorGrid(const HitPointBuffer& hits, int stride);

// Whether a sample lies on the same smooth piece of the relic as an anchor.
bool sameSurface(const RefractionAnchor& a, const HitPoint& hp);

// Whether a sample took its anchors' blend, and if not, whether the anchors around it meet other
// events inside (another number of interface events, or one exited and one capped): the path
// changes within a pixel there (a facet's edge, a total internal reflection that starts).
enum class Blend { Blended, NotBlended, EventsDiffer };

// The bilinear blend at image position `at` (pixels, pixel centres at integers) of the anchors
// `step` grid points apart (1: all of them; 2: the coarse lattice of every second one each way),
// per unit of entry, and which anchors it took with which weights (source); where it is not
// Blended the sample must trace its own path.
Blend blendAnchors(const std::vector<RefractionAnchor>& anchors, const AnchorGrid& grid, int step,
                   const HitPoint& hp, const vec2& at, TransmittedPath& out, WalkSource& source);

// The anchor whose path was traced from sample i of pixel p (p on the lattice, i the sample
// traceAnchors took there, the anchor traced rather than blended), or null: where non-null its
// path per unit of entry is sample i's own, and the sample need not trace it again.
const RefractionAnchor* anchorTracedAt(const std::vector<RefractionAnchor>& anchors, const AnchorGrid& grid,
                                       const HitPointBuffer& hits, std::size_t p, std::size_t i);

// Every anchor of `grid` into `anchors` (resized to grid.size()), in two rounds: the coarse
// lattice's anchors (even grid coordinates) trace their paths; every other anchor takes their blend
// where they agree as a sample does, else traces its own. Returns the Embree rays cast.
std::uint64_t traceAnchors(const RenderScene& scene, const PrefilteredIbl& ibl,
                           const TracerSettings& settings, int depth, const HitPointBuffer& hits,
                           const AnchorGrid& grid, std::vector<RefractionAnchor>& anchors);

// The anchors whose paths leave the relic (the exit rays walked every frame), indices into the
// anchor grid, ascending: those that traced their own path and those that took the coarse
// anchors' blend. Most of a view's grid is off the relic: the walks visit these alone.
struct AnchorExits {
  std::vector<std::uint32_t> traced, blended;
};
AnchorExits anchorExits(const std::vector<RefractionAnchor>& anchors);

// This frame's walk of each exiting anchor's exit ray into anchor_fg (resized to anchors.size();
// the other entries are left empty), in two rounds as they were traced: a blended anchor blends
// the coarse anchors' walks where these agree. Returns the rays walked.
std::uint64_t walkAnchors(const std::vector<RefractionAnchor>& anchors, const AnchorExits& exits,
                          const ForegroundWalk& walk, std::vector<ForegroundSample>& anchor_fg);

// The blend of the anchors' walks a blended sample's path took (premultiplied by the mask, so it
// composes as the blend of theirs), where they see the same: no visitor, or the same visitor's
// colour within 10% of the brightest; false where the sample walks its own exit ray.
bool blendWalks(const std::vector<ForegroundSample>& anchor_fg, const WalkSource& source,
                ForegroundSample& out);

}  // namespace holo::reflect
