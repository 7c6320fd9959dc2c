#include "foreground_walk.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/reflect/voxel_walk.hpp"

namespace holo::reflect {
namespace {

// How deep a sharp read follows its ray through the occupied voxels for the visitor's silhouette
// (voxels): a limb's thickness, so that the body behind a limb is left to addLayerBehind. It does
// where the read at the entry shows less than kBesideSilhouette of the visitor: the point lies
// beside the silhouette, within the bilinear read's pixel of it.
constexpr float kSilhouetteRunVoxels = 3.0f;
constexpr float kBesideSilhouette = 0.2f;

// The occupied voxels' box grown by a voxel on every side (metres) and a reach beyond the walk's
// longest: a ray that misses it within [0, reach] misses the exact box that firstOccupiedVoxel
// clips to by at least a voxel, far beyond round-off, and so meets no voxel. Likewise the boxes of
// the grid's occupied groups, each grown by a voxel: every occupied voxel lies in one, so a ray
// that misses them all meets none; where visitors stand apart they leave out the space between
// them, which the one box spans. Most of a frame's mirror rays miss them; testing a block of rays
// together (vectorised) costs a fraction of setting up a walk for each.
struct CullBoxes {
  vec3 lo{0.0f}, hi{-1.0f};  // empty unless some voxel is occupied
  float reach = 0.0f;
  std::array<vec3, VoxelGrid::kMaxOccupiedGroups> group_lo{}, group_hi{};
  std::size_t groups = 0;  // 0 where one group holds every voxel: the box alone
};

CullBoxes cullBoxesOf(const VoxelGrid& grid, float t_max) {
  CullBoxes boxes;
  const glm::ivec3 lo = grid.occupiedLo(), hi = grid.occupiedHi();
  if (grid.empty() || glm::any(glm::greaterThanEqual(lo, hi))) return boxes;
  const float size = grid.voxelSize();
  boxes.lo = grid.origin() + vec3(lo - 1) * size;
  boxes.hi = grid.origin() + vec3(hi + 1) * size;
  boxes.reach = t_max * 1.001f + size;
  const std::vector<VoxelGrid::VoxelBox>& groups = grid.occupiedGroups();
  if (groups.size() > 1)
    for (const VoxelGrid::VoxelBox& g : groups) {
      boxes.group_lo[boxes.groups] = grid.origin() + vec3(g.lo - 1) * size;
      boxes.group_hi[boxes.groups] = grid.origin() + vec3(g.hi + 1) * size;
      ++boxes.groups;
    }
  return boxes;
}

// A block of rays (origins o, unit directions d, structure of arrays) against the boxes: may[j] is
// 0 only where ray j cannot meet the occupied box or cannot meet any group's. Branch-free. A zero
// direction component gives infinite slab distances, and NaN only for a ray lying in one of a grown
// box's planes, a voxel outside the exact one, which it never meets; whatever the test says of
// such a ray, or of a non-finite one (which the walk misses), the result is the walk's.
template <std::size_t N>
void mayMeetBoxes(const CullBoxes& boxes, std::size_t n, const std::array<std::array<float, N>, 3>& o,
                  const std::array<std::array<float, N>, 3>& d, std::array<std::uint8_t, N>& may) {
  std::array<std::array<float, N>, 3> inv;
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t j = 0; j < n; ++j) inv[a][j] = 1.0f / d[a][j];
  const auto meets = [&](const vec3& lo, const vec3& hi, std::size_t j) {
    float t0 = 0.0f, t1 = boxes.reach;
    for (int a = 0; a < 3; ++a) {
      const float ta = (lo[a] - o[std::size_t(a)][j]) * inv[std::size_t(a)][j],
                  tb = (hi[a] - o[std::size_t(a)][j]) * inv[std::size_t(a)][j];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    return std::uint8_t(!(t0 > t1));
  };
  for (std::size_t j = 0; j < n; ++j) may[j] = meets(boxes.lo, boxes.hi, j);
  if (boxes.groups == 0) return;
  std::array<std::uint8_t, N> any{};
  for (std::size_t g = 0; g < boxes.groups; ++g)
    for (std::size_t j = 0; j < n; ++j) any[j] |= meets(boxes.group_lo[g], boxes.group_hi[g], j);
  for (std::size_t j = 0; j < n; ++j) may[j] &= any[j];
}

// Pixel state of a pixel whose sub-samples reflect partly off the relic itself: no pixel walk.
constexpr std::uint8_t kMixedBounce = 3;

// A pixel's one walk in pass 1: the mean of its valid samples' rays.
struct PixelRay {
  std::size_t pixel;
  vec3 position, normal, reflected;
  float roughness;
};

// Pixel p's mean ray, when it has one to walk. Sets its state: left 0 without a valid sample,
// kMixedBounce where its samples reflect partly off the relic (they walk one by one, pass 2),
// else 1 (opposite samples whose means vanish walk nothing).
std::optional<PixelRay> meanPixelRay(const HitPointBuffer& hits, const std::vector<WalkRay>& walk_rays,
                                     std::size_t p, std::uint8_t& state) {
  const std::size_t first = hits.firstSample(p), count = std::size_t(hits.sampleCount(p));
  vec3 position(0.0f), normal(0.0f), reflected(0.0f);
  float roughness = 0.0f;
  int valid = 0, bounced = 0;
  for (std::size_t i = first; i < first + count; ++i) {
    if (!hits.valid[i]) continue;
    const WalkRay& wr = walk_rays[i];
    position += wr.position;
    normal += wr.normal;
    reflected += wr.reflected;
    roughness += wr.roughness;
    bounced += wr.bounced;
    ++valid;
  }
  if (valid == 0) return std::nullopt;
  state = bounced != 0 && bounced != valid ? kMixedBounce : 1;
  const float inv = 1.0f / float(valid);
  const float nl = glm::length(normal), rl = glm::length(reflected);
  if (!(nl > 1e-6f) || !(rl > 1e-6f) || state == kMixedBounce) return std::nullopt;
  return PixelRay{p, position * inv, normal / nl, reflected / rl, roughness * inv};
}

}  // namespace

std::optional<float> nearMissT(const VoxelGrid& grid, const Ray& ray, float t_max, float radius_per_m) {
  const float brick_m = grid.voxelSize() * float(grid.brickSize());
  const Bounds3 box{grid.origin(), grid.origin() + vec3(grid.dims()) * grid.voxelSize()};
  float t0 = 0.0f, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == 0.0f) {
      if (!(ray.origin[a] >= box.lo[a] && ray.origin[a] < box.hi[a])) return std::nullopt;
      continue;
    }
    const float inv = 1.0f / ray.direction[a];
    float ta = (box.lo[a] - ray.origin[a]) * inv, tb = (box.hi[a] - ray.origin[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  const glm::ivec3 bricks = grid.brickDims();
  // The ray in brick units, so that a step's brick is one floor.
  const vec3 origin_b = (ray.origin - box.lo) / brick_m, direction_b = ray.direction / brick_m;
  // Every iteration advances t by at least half a brick: the loop is bounded by the box.
  for (float t = std::max(t0, 0.5f * brick_m); t <= t1;) {
    const vec3 at = glm::floor(origin_b + direction_b * t);
    if (glm::any(glm::lessThan(at, vec3(0.0f))) || glm::any(glm::greaterThanEqual(at, vec3(bricks)))) break;
    const glm::ivec3 b(at);
    const float gap = float(std::max(int(grid.brickDistance(b)) - 1, 0)) * brick_m;
    const float radius = radius_per_m * t;
    if (grid.brickCount(b) > 0 || gap <= radius) return t;
    t += std::max(0.5f * brick_m, gap - radius_per_m * (t + gap));
  }
  return std::nullopt;
}

float nearestPassT(const VoxelGrid& grid, const Ray& ray, float t_near, float t_max) {
  const float brick_m = grid.voxelSize() * float(grid.brickSize());
  const glm::ivec3 bricks = grid.brickDims();
  float best_t = t_near;
  int best = 256, max_steps = 0;
  // A ray heading for the nearest occupied brick, k bricks away, reaches it within 2 (k + 1) half
  // bricks; a ray moving away (k grows) has passed its nearest point.
  for (int step = 0; step <= max_steps; ++step) {
    const float t = t_near + float(step) * 0.5f * brick_m;
    if (t > t_max) break;
    const vec3 at = glm::floor((ray.origin + ray.direction * t - grid.origin()) / brick_m);
    if (glm::any(glm::lessThan(at, vec3(0.0f))) || glm::any(glm::greaterThanEqual(at, vec3(bricks)))) break;
    const int k = grid.brickDistance(glm::ivec3(at));
    if (step == 0) max_steps = 2 * (k + 1);
    if (k > best) break;
    if (k < best) best = k, best_t = t;
    if (best == 0) break;
  }
  return best_t;
}

std::optional<CameraPixel> cameraAlong(const std::vector<ForegroundCameraImage>& cameras,
                                       const std::vector<ForegroundPyramid>& pyramids, const vec3& point,
                                       const vec3& direction) {
  std::optional<CameraPixel> best;
  float best_dot = -2.0f;
  for (std::size_t c = 0; c < pyramids.size(); ++c) {
    if (pyramids[c].empty()) continue;
    const CameraModel& cam = cameras[c].camera;
    float depth = 0.0f;
    const std::optional<vec2> px = cam.project(point, &depth);
    if (!px || !(depth > 0.0f) || px->x < 0.0f || px->y < 0.0f || px->x > float(cam.width() - 1) ||
        px->y > float(cam.height() - 1))
      continue;
    const float d = glm::dot(direction, glm::normalize(vec3(cam.T_world_camera()[2])));
    if (d > best_dot) best_dot = d, best = CameraPixel{c, *px};
  }
  return best;
}

ForegroundWalk::ForegroundWalk(const TracerSettings& settings, const VoxelGrid& grid,
                               const std::vector<ForegroundPyramid>& pyramids,
                               const std::vector<ForegroundCameraImage>& cameras,
                               const RoughForegroundMap* rough_map)
    : settings_(settings),
      grid_(grid),
      pyramids_(pyramids),
      cameras_(cameras),
      rough_map_(rough_map),
      lobe_(ggxLobeMixture(settings.lobe_components)) {}

// The pyramid's blurred foreground at `pixel` for a lobe of `roughness` that travelled travel_m to
// a point camera_m from the camera: one read per Gaussian of the lobe, the premultiplied colours
// and the weights mixed.
ForegroundSample ForegroundWalk::readLobe(const ForegroundPyramid& pyramid, const vec2& pixel,
                                          float roughness, float travel_m, float camera_m,
                                          float focal_px) const {
  const float sigma = reflectedLobeSigma(roughness);
  ForegroundSample mixed;
  vec3 premultiplied(0.0f);
  // Components whose level is the previous one's read the same sample (the lobe of a near-mirror
  // reads level 0 for all of them).
  float read_level = -1.0f;
  ForegroundSample s;
  for (const LobeComponent& c : lobe_) {
    const float level = std::clamp(foregroundLevelForLobe(sigma * c.sigma_scale, travel_m, camera_m, focal_px,
                                                          settings_.pyramid_levels) +
                                       settings_.evaluation.level_bias,
                                   0.0f, float(settings_.pyramid_levels - 1));
    if (level != read_level) {
      s = pyramid.sample(pixel, level);
      read_level = level;
    }
    premultiplied += c.weight * s.weight * s.radiance;
    mixed.weight += c.weight * s.weight;
  }
  if (mixed.weight > 0.0f) mixed.radiance = premultiplied / mixed.weight;
  return mixed;
}

bool ForegroundWalk::missReadsNothing(float roughness) const {
  return !readsRoughMap(rough_map_, settings_, roughness) && roughness < settings_.lobe_fallback_roughness;
}

bool ForegroundWalk::walk(const vec3& position, const vec3& normal, const vec3& reflected, float roughness,
                          ForegroundSample& sample) const {
  if (readsRoughMap(rough_map_, settings_, roughness)) {
    sample = rough_map_->lookup(reflected, roughness);
    return sample.weight > 0.0f;
  }
  const Ray ray{position + normal * settings_.ray_offset, reflected};
  const VoxelHit vh = firstOccupiedVoxel(grid_, ray, settings_.max_reflection_distance);
  if (!vh.hit()) {
    if (missReadsNothing(roughness)) return false;
    const float tan_sigma = std::tan(reflectedLobeSigma(roughness));
    const std::optional<float> t_near =
        nearMissT(grid_, ray, settings_.max_reflection_distance, 2.0f * tan_sigma);
    if (!t_near) return false;
    // Read where the ray passes nearest the visitor, not at the first point near a brick: that one
    // can lie bricks in front of the visitor, where no camera looks (above the image of a camera
    // under a visitor close to the pyramid) or where a camera sees something else.
    const float t = nearestPassT(grid_, ray, *t_near, settings_.max_reflection_distance);
    const vec3 p = ray.origin + ray.direction * t;
    const std::optional<CameraPixel> seen = cameraAlong(cameras_, pyramids_, p, ray.direction);
    if (!seen) return false;
    const CameraModel& cam = cameras_[seen->camera].camera;
    sample = readLobe(pyramids_[seen->camera], seen->pixel, roughness, t, glm::length(p - cam.position()),
                      cam.intrinsics().fx);
    return sample.weight > 0.0f;
  }
  if (!readHit(ray, vh, roughness, sample)) return false;
  if (sample.weight < 1.0f) addLayerBehind(ray, vh, roughness, sample);
  return true;
}

bool ForegroundWalk::readHit(const Ray& ray, const VoxelHit& hit, float roughness,
                             ForegroundSample& sample) const {
  const VoxelSample& vs = grid_.sample(hit.sample);
  if (vs.camera >= pyramids_.size() || pyramids_[vs.camera].empty()) return false;
  const ForegroundPyramid& pyramid = pyramids_[vs.camera];
  const CameraModel& cam = cameras_[vs.camera].camera;
  const float voxel = grid_.voxelSize();
  // The point the ray reaches: half a voxel into the one it entered.
  const vec3 p = ray.origin + ray.direction * (hit.t + 0.5f * voxel);
  const float camera_m = glm::length(p - cam.position()), focal_px = cam.intrinsics().fx;
  const vec2 source(vs.x, vs.y);
  const std::optional<vec2> px = cam.project(p);
  sample = readLobe(pyramid, px ? *px : source, roughness, hit.t, camera_m, focal_px);
  if (!px || !(sample.weight < 1.0f)) return true;
  // A voxel is wider than a limb seen from a metre (3 cm against a 5-10 cm arm): the point a rough
  // ray entered can project beside the camera's silhouette, where the blurred mask is mostly the
  // hall. The pixel the camera saw the voxel at lies inside it; where the lobe's blur is at least
  // half a voxel wide in that camera the two reads differ by the voxel's quantisation alone, and
  // the better covered one stands for the voxel.
  if (pyramidSigmaPx(foregroundLevel(roughness, hit.t, camera_m, focal_px, settings_.pyramid_levels)) >=
      0.5f * voxel * focal_px / camera_m) {
    const ForegroundSample at_source = readLobe(pyramid, source, roughness, hit.t, camera_m, focal_px);
    if (at_source.weight > sample.weight) sample = at_source;
    return true;
  }
  // A sharper read is the silhouette test itself: a mirror's ray that enters the voxels beside the
  // visitor's silhouette misses the visitor. But the voxels stand up to a voxel or two in front of
  // the visitor's surface, so a ray that meets the visitor further in can enter them beside it too
  // (a close visitor seen at a slant by the camera, in a crystal's table): where the entry point
  // shows (almost) none of the visitor, the ray is followed on through the run of occupied voxels,
  // each point read in the camera that saw the voxel it is in, and the best covered point is kept.
  if (!(sample.weight < kBesideSilhouette)) return true;
  for (float t = hit.t + 0.75f * voxel; t <= hit.t + kSilhouetteRunVoxels * voxel; t += 0.25f * voxel) {
    const vec3 q = ray.origin + ray.direction * t;
    const glm::ivec3 v = grid_.voxelOf(q);
    if (!grid_.occupied(v)) break;
    const VoxelSample& there = grid_.sample(grid_.sampleIndex(v));
    if (there.camera >= pyramids_.size() || pyramids_[there.camera].empty()) continue;
    const CameraModel& seen_by = cameras_[there.camera].camera;
    const std::optional<vec2> qx = seen_by.project(q);
    if (!qx) continue;
    const ForegroundSample deeper = readLobe(pyramids_[there.camera], *qx, roughness, t,
                                             glm::length(q - seen_by.position()), seen_by.intrinsics().fx);
    if (deeper.weight > sample.weight) sample = deeper;
    if (!(sample.weight < 1.0f)) break;
  }
  return true;
}

void ForegroundWalk::addLayerBehind(const Ray& ray, const VoxelHit& front, float roughness,
                                    ForegroundSample& sample) const {
  const float step = 0.5f * grid_.voxelSize(), t_max = settings_.max_reflection_distance;
  float t = front.t + step;
  glm::ivec3 last = front.voxel;
  for (glm::ivec3 v; t < t_max && grid_.occupied(v = grid_.voxelOf(ray.origin + ray.direction * t));
       t += step)
    last = v;
  if (!(t < t_max)) return;
  VoxelHit behind = firstOccupiedVoxel(grid_, Ray{ray.origin + ray.direction * t, ray.direction}, t_max - t);
  // Stepped out exactly on a voxel's face, the walk can start in the voxel just left.
  if (!behind.hit() || behind.voxel == last) return;
  behind.t += t;
  ForegroundSample back;
  if (!readHit(ray, behind, roughness, back) || !(back.weight > sample.weight)) return;
  // The limb covers part of the same lobe its body behind covers (the two overlap, they are not
  // independent layers): the lobe's coverage is the larger of the two, and the body fills the
  // part the limb leaves.
  const vec3 premultiplied = sample.radiance * sample.weight + back.radiance * (back.weight - sample.weight);
  sample.weight = back.weight;
  sample.radiance = premultiplied / back.weight;
}

WalkCounts ForegroundWalk::walkView(const HitPointBuffer& hits, const std::vector<WalkRay>& walk_rays,
                                    WalkScratch& scratch, std::vector<ForegroundSample>& fg) const {
  std::atomic<std::uint64_t> walked{0}, found{0};
  const std::size_t pixels = hits.pixelCount();
  const std::vector<std::uint32_t>& covered = hits.covered;
  // Pass 1: one walk per covered pixel (its centre, or the mean ray of its valid
  // sub-samples). Pixel states: 0 nothing of the relic, 1 its walk missed, 2 it met the
  // foreground, kMixedBounce no walk.
  scratch.pixel_fg.resize(pixels);
  scratch.pixel_state.assign(pixels, 0);
  const CullBoxes boxes = cullBoxesOf(grid_, settings_.max_reflection_distance);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, covered.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t local_walked = 0, local_found = 0;
        // The pixels' rays in blocks: gathered, tested against the box together, then walked where
        // they may meet it (or where a miss still reads the visitors: rough map, lobe fallback).
        constexpr std::size_t kBlock = 64;
        std::array<PixelRay, kBlock> rays;
        std::array<std::array<float, kBlock>, 3> origins, directions;
        std::array<std::uint8_t, kBlock> may_meet;
        for (std::size_t b = r.begin(); b < r.end(); b += kBlock) {
          std::size_t n = 0;
          for (std::size_t k = b; k < std::min(r.end(), b + kBlock); ++k) {
            const std::size_t p = covered[k];
            scratch.pixel_fg[p] = ForegroundSample{};
            const std::size_t first = hits.firstSample(p);
            for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
              fg[i] = ForegroundSample{};
            const std::optional<PixelRay> ray = meanPixelRay(hits, walk_rays, p, scratch.pixel_state[p]);
            if (!ray) continue;
            const vec3 origin = ray->position + ray->normal * settings_.ray_offset;
            for (std::size_t a = 0; a < 3; ++a) {
              origins[a][n] = origin[int(a)];
              directions[a][n] = ray->reflected[int(a)];
            }
            rays[n++] = *ray;
          }
          mayMeetBoxes(boxes, n, origins, directions, may_meet);
          for (std::size_t j = 0; j < n; ++j) {
            const PixelRay& ray = rays[j];
            ++local_walked;
            if (!may_meet[j] && missReadsNothing(ray.roughness)) continue;
            if (!walk(ray.position, ray.normal, ray.reflected, ray.roughness, scratch.pixel_fg[ray.pixel]))
              continue;
            ++local_found;
            scratch.pixel_state[ray.pixel] = 2;
          }
        }
        walked += local_walked;
        found += local_found;
      });
  // Pass 2: a pixel with four sub-samples keeps its one walk where its lobe is rough, or where
  // the foreground it met (or missed) matches its 8 neighbours'; at the reflected foreground's
  // edges (a neighbour met it and this one did not, or their weights differ by more than
  // kEdgeWeightStep) each sub-sample walks, which anti-aliases those edges as four walks
  // everywhere would.
  constexpr float kEdgeWeightStep = 0.2f;
  const int w_px = hits.width, h_px = hits.height;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, covered.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t local_walked = 0, local_found = 0;
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const std::size_t p = covered[k];
          if (scratch.pixel_state[p] == 0) continue;
          const std::size_t first = hits.firstSample(p);
          const std::size_t count = std::size_t(hits.sampleCount(p));
          const bool mixed = scratch.pixel_state[p] == kMixedBounce;
          if (count == 1 && !mixed) {
            // One sample: its walk was the pixel's.
            if (scratch.pixel_state[p] == 2 && hits.valid[first]) fg[first] = scratch.pixel_fg[p];
            continue;
          }
          bool rough = !mixed;
          for (std::size_t i = first; i < first + count && rough; ++i)
            rough = !hits.valid[i] || walk_rays[i].roughness >= settings_.walk_per_pixel_roughness;
          bool edge = false;
          if (count > 1 && !rough && settings_.evaluation.walk_edges_only) {
            const int x = int(p % std::size_t(w_px)), y = int(p / std::size_t(w_px));
            for (int dy = -1; dy <= 1 && !edge; ++dy)
              for (int dx = -1; dx <= 1 && !edge; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w_px || ny >= h_px) continue;
                const std::size_t q = std::size_t(ny) * std::size_t(w_px) + std::size_t(nx);
                if (scratch.pixel_state[q] == 0) continue;  // beyond the relic's silhouette
                edge = scratch.pixel_state[q] != scratch.pixel_state[p] ||
                       std::abs(scratch.pixel_fg[q].weight - scratch.pixel_fg[p].weight) > kEdgeWeightStep;
              }
          }
          if (mixed || (count > 1 && !rough && (edge || !settings_.evaluation.walk_edges_only))) {
            for (std::size_t i = first; i < first + count; ++i) {
              if (!hits.valid[i]) continue;
              const WalkRay& wr = walk_rays[i];
              ++local_walked;
              local_found += walk(wr.position, wr.normal, wr.reflected, wr.roughness, fg[i]);
            }
            continue;
          }
          if (scratch.pixel_state[p] != 2) continue;
          for (std::size_t i = first; i < first + count; ++i)
            if (hits.valid[i]) fg[i] = scratch.pixel_fg[p];
        }
        walked += local_walked;
        found += local_found;
      });
  return {walked, found};
}

}  // namespace holo::reflect
