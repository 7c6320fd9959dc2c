// The frame renderer's foreground pass (internal): per hit point of a view, the foreground
// radiance psi_d and weight w its reflected ray meets (paper step 4).
//
// One ray: the first occupied voxel of the grid (voxel_walk.hpp), read from the pyramid of the
// camera that saw that voxel at the levels of the ray's GGX lobe (one read per Gaussian of
// ggxLobeMixture) and travel distance, and where that leaves the lobe partly uncovered the next
// voxel behind; a rough ray that meets no voxel marches to where it first
// passes within two lobe sigmas of an occupied brick (nearMissT) and reads there from the camera
// looking most along it (cameraAlong); materials read from the rough map take its lookup instead.
//
// A view: pass 1 walks each covered pixel once (its centre, or the mean ray of its samples);
// pass 2 lets every sample of a four-sample pixel walk where the relic is smooth and the pixel
// sits at the reflected foreground's edge (walk_edges_only), or its samples reflect partly off
// the relic itself; elsewhere the samples share the pixel's walk.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/tracer_settings.hpp"
#include "holo/reflect/voxel_grid.hpp"
#include "holo/reflect/voxel_walk.hpp"
#include "walk_ray.hpp"

namespace holo::reflect {

// Where a ray that misses every voxel first passes within `radius_per_m * t` metres of an occupied
// brick, for t in (0, t_max]; none when it never does. Marches the brick level by steps of half a
// brick, jumping where the brick distance proves the space around empty: a brick at Chebyshev
// distance k (in bricks) from the nearest occupied one is at least (k - 1) bricks from any
// occupied voxel. So the t returned is within half a brick of the first such point.
std::optional<float> nearMissT(const VoxelGrid& grid, const Ray& ray, float t_max, float radius_per_m);

// From a near miss at t_near on, where the ray passes nearest the visitors: the first t (steps of
// half a brick, up to t_max) of the smallest brick distance, marching while that distance does
// not grow and no longer than it takes to cross it. A ray that slips through a gap in a visitor's
// voxels passes through an occupied brick: that point lies at the visitor's depth, where the
// first near point (one or more bricks in front of it) does not.
float nearestPassT(const VoxelGrid& grid, const Ray& ray, float t_near, float t_max);

// The camera whose optical axis is closest to `direction` among those with a pyramid that see
// `point` in front of them and inside the image, and the pixel it sees it at; none when no
// camera does.
struct CameraPixel {
  std::size_t camera = 0;
  vec2 pixel{0.0f};
};
std::optional<CameraPixel> cameraAlong(const std::vector<ForegroundCameraImage>& cameras,
                                       const std::vector<ForegroundPyramid>& pyramids, const vec3& point,
                                       const vec3& direction);

// Scratch of one view's walk, reused from frame to frame.
struct WalkScratch {
  std::vector<ForegroundSample> pixel_fg;  // per pixel, the walk of its centre or mean ray
  // Per pixel: 0 no relic, 1 walk missed, 2 met, 3 no pixel walk (its samples' rays reflect
  // partly off the relic itself).
  std::vector<std::uint8_t> pixel_state;
};

struct WalkCounts {
  std::uint64_t walked = 0, found = 0;  // rays walked; those that met the foreground
};

class ForegroundWalk {
 public:
  // Everything must outlive this; pyramids[c] belongs to cameras[c] (an empty one: the camera has
  // no image this frame); rough_map may be null.
  ForegroundWalk(const TracerSettings& settings, const VoxelGrid& grid,
                 const std::vector<ForegroundPyramid>& pyramids,
                 const std::vector<ForegroundCameraImage>& cameras, const RoughForegroundMap* rough_map);

  // The foreground one reflected ray meets from `position` (offset along `normal`); false (and
  // `sample` untouched) when it meets none.
  bool walk(const vec3& position, const vec3& normal, const vec3& reflected, float roughness,
            ForegroundSample& sample) const;
  // Every covered pixel's samples of `hits`: fg[i] (per entry of hits.hits, sized by the caller)
  // the foreground of sample i, weight 0 where none. walk_rays as StaticShading wrote them.
  WalkCounts walkView(const HitPointBuffer& hits, const std::vector<WalkRay>& walk_rays, WalkScratch& scratch,
                      std::vector<ForegroundSample>& fg) const;

 private:
  ForegroundSample readLobe(const ForegroundPyramid& pyramid, const vec2& pixel, float roughness,
                            float travel_m, float camera_m, float focal_px) const;
  // The foreground where `ray` entered the voxel of `hit` (hit.t from ray.origin), read in the
  // camera that saw that voxel (a sharp read that shows almost none of the visitor there: the
  // best covered point of the ray followed on through the occupied voxels, each read in the camera
  // that saw its voxel); false when that camera has no image this frame.
  bool readHit(const Ray& ray, const VoxelHit& hit, float roughness, ForegroundSample& sample) const;
  // Whether a ray of this roughness that meets no voxel reads nothing either (it reads neither the
  // rough map nor, falling back, the visitors it passes near): walk() gives up on it at once, and
  // walkView need not walk it once it is known to miss.
  bool missReadsNothing(float roughness) const;
  // Where the front read covers part of the lobe only (none: a mirror ray that entered the voxel
  // hull beside the visitor's silhouette): the ray steps out of the voxels it met (a limb) and
  // walks on; a visitor behind (the limb's body, seen by the relic around the limb where the
  // camera under the limb sees the hall) raises the coverage to its own.
  void addLayerBehind(const Ray& ray, const VoxelHit& front, float roughness, ForegroundSample& sample) const;

  const TracerSettings& settings_;
  const VoxelGrid& grid_;
  const std::vector<ForegroundPyramid>& pyramids_;
  const std::vector<ForegroundCameraImage>& cameras_;
  const RoughForegroundMap* rough_map_;
  std::vector<LobeComponent> lobe_;
};

}  // namespace holo::reflect
