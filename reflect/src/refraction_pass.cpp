#include "refraction_pass.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "foreground_walk.hpp"
#include "holo/core/fibonacci_sphere.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/dfg_table.hpp"

namespace holo::reflect {
namespace {

float luminance(const vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// Snell refraction of d (unit, against n) through an interface with eta = n_t / n_i; the caller
// has checked that it is not totally reflected.
vec3 refractThrough(const vec3& d, const vec3& n, float eta) {
  const float cos_i = std::clamp(-glm::dot(d, n), 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
  const vec3 t = d / eta + (cos_i / eta - cos_t) * n;
  const float len = glm::length(t);
  return len > 1e-12f ? t / len : d;
}

// The prefiltered IBL a ray from `origin` along `direction` reads: through the panorama's proxy,
// so the hall's parallax is the same as the static shading's.
vec3 seenFrom(const PrefilteredIbl& ibl, const vec3& origin, const vec3& direction, float roughness) {
  return ibl.specular(ibl.proxy().lookupDirection(origin, direction), roughness);
}

float clamp01(float v) {
  return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
}

// The radiance a path brings to its sample before the visitors: the IBL along its exit and what
// it read on the way.
float transmittedLight(const TransmittedPath& path) {
  return luminance(path.scale * path.environment + path.resolved);
}

// Beer-Lambert coefficient per metre of a volume material; 0 for a clear one.
vec3 absorptionCoefficient(const Material& m) {
  const float distance = m.attenuation_distance;
  if (!std::isfinite(distance) || !(distance > 0.0f)) return vec3(0.0f);
  vec3 sigma;
  for (int c = 0; c < 3; ++c)
    sigma[c] = -std::log(std::clamp(m.attenuation_colour[c], 1e-6f, 1.0f)) / distance;
  return sigma;
}

float safeIor(float ior) {
  return std::isfinite(ior) && ior >= 1.0f ? ior : 1.0f;
}

// An interface's transmitted share of the light past its Fresnel reflection, and the tint it
// transmits with: the entry's as its hit point sampled the textures, later hits' factors.
float transmittedShare(const Material& m, const SurfaceMaterial* textured) {
  return (1.0f - clamp01(textured ? textured->metallic : m.metallic)) *
         clamp01(textured ? textured->transmission : m.transmission);
}

vec3 transmissionTint(const Material& m, const SurfaceMaterial* textured) {
  return glm::clamp(textured ? textured->base_colour : m.base_colour, vec3(0.0f), vec3(1.0f));
}

// The parallel-walls sum at a partial exit with reflectance `fresnel` and the last segment's
// absorption: `back` leaves along the refracted ray, `front` back towards the side the light came
// from, per unit arriving.
void parallelWalls(float fresnel, const vec3& last_absorption, vec3& back, vec3& front) {
  for (int c = 0; c < 3; ++c) {
    const float fa = fresnel * last_absorption[c];
    const float denom = (1.0f - fa) * (1.0f + fa);
    back[c] = (1.0f - fresnel) / denom;
    front[c] = fa * (1.0f - fresnel) / denom;
  }
}

// The transmitted lobe's perceptual roughness from its GGX alpha^2 summed in quadrature.
float lobeWidth(const TracerSettings& settings, float alpha2) {
  return std::clamp(std::sqrt(std::sqrt(alpha2)) * settings.evaluation.transmitted_roughness_scale, 0.0f, 1.0f);
}

// The light reflected inside at a partial exit, followed explicitly: `weight` per unit entering
// leaves `position` along `direction` inside a volume of IOR medium_ior and absorption sigma;
// `behind` is the IBL the light refracted out at that exit reads. At each partial exit the
// refracted share reads the prefiltered IBL at the lobe's width into path.resolved and the
// reflected share goes on while it is at least TracerSettings::refraction_branch_weight and
// `budget` has a ray left. Where it stops, the parallel-walls sum takes the rest: what it sends
// back leaves through the face the light last reflected from, along that face's refracted ray
// (after a total internal reflection there: it joins path.reflected, as in the main path). A ray
// that meets nothing or a thin wall gives what it carries to the IBL along its direction; one out
// of budget after a total internal reflection, to path.reflected. Each ray cast takes one from
// `budget`.
void followReflected(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                     vec3 position, vec3 direction, vec3 weight, float alpha2, const vec3& sigma,
                     float medium_ior, vec3 behind, int& budget, TransmittedPath& path) {
  const RayScene& relic = scene.relicOnly();
  const float offset = std::max(settings.ray_offset, 1e-5f);
  bool has_behind = true;
  const float eta = 1.0f / medium_ior;
  for (;;) {
    const Ray ray{position, direction};
    const RayHit hit = relic.intersect(ray, offset);
    ++path.rays;
    --budget;
    if (!hit.hit()) break;
    vec3 last_absorption;
    for (int c = 0; c < 3; ++c) last_absorption[c] = std::exp(-sigma[c] * hit.t);
    weight *= last_absorption;
    position = relic.position(ray, hit);
    vec3 normal = relic.shadingNormal(hit, direction);
    const Material& m = scene.relicGltfMaterial(hit, relic);
    if (!isFinite(position) || !isFinite(normal) || !(m.thickness > 0.0f)) break;
    float cos_i = -glm::dot(direction, normal);
    if (!(cos_i > 1e-6f)) {
      normal = hit.geometric_normal;
      cos_i = std::max(-glm::dot(direction, normal), 1e-6f);
    }
    const float fresnel = fresnelDielectric(cos_i, eta);
    const float alpha = clamp01(m.roughness) * clamp01(m.roughness);
    const vec3 reflected_direction = glm::reflect(direction, normal);
    if (fresnel >= 1.0f) {
      direction = reflected_direction;
      alpha2 += alpha * alpha;
      has_behind = false;
      if (budget > 0) continue;
      path.reflected += weight;
      return;
    }
    const float transmitted = transmittedShare(m, nullptr);
    const vec3 tint = transmissionTint(m, nullptr);
    const float spread = alpha * std::min(safeIor(m.ior) - 1.0f, 2.0f) * 0.5f;
    const vec3 outside = seenFrom(ibl, position, refractThrough(direction, normal, eta),
                                  lobeWidth(settings, alpha2 + spread * spread));
    const vec3 lit =
        transmitted < 1.0f ? (1.0f - transmitted) * tint * ibl.irradiance(-normal) / kPi : vec3(0.0f);
    if (budget > 0 && luminance(weight) * fresnel >= settings.refraction_branch_weight) {
      path.resolved += weight * (1.0f - fresnel) * (transmitted * tint * outside + lit);
      weight *= fresnel;
      direction = reflected_direction;
      alpha2 += alpha * alpha;
      behind = outside;
      has_behind = true;
      continue;
    }
    vec3 back, front;
    parallelWalls(fresnel, last_absorption, back, front);
    path.resolved += weight * (back * transmitted * tint * outside + (back + front) * lit);
    if (has_behind)
      path.resolved += weight * front * transmitted * tint * behind;
    else
      path.reflected += weight * front * transmitted * tint;
    return;
  }
  path.resolved += weight * seenFrom(ibl, position, direction, lobeWidth(settings, alpha2));
}

// The path per unit of light entering: scale, resolved and reflected leave out path.entry, which
// the caller multiplies in (traceTransmission), or a neighbour's own (a blended sample).
TransmittedPath traceUnit(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                          int depth, const vec3& entry_position, const vec3& entry_normal,
                          const vec3& entry_direction, const Material& entry,
                          const SurfaceMaterial* entry_textured, std::vector<double>* alive) {
  TransmittedPath path;
  const RayScene& relic = scene.relicOnly();
  const float offset = std::max(settings.ray_offset, 1e-5f);
  vec3 throughput(1.0f), last_absorption(1.0f), sigma(0.0f);
  vec3 position = entry_position, normal = entry_normal, geometric = entry_normal;
  vec3 direction = entry_direction;
  const Material* material = &entry;
  bool inside = false;
  float medium_ior = 1.0f, alpha2 = 0.0f;
  int branch_budget = settings.refraction_branch_rays;
  const auto lobe = [&] { return lobeWidth(settings, alpha2); };
  for (;;) {
    // One interface event at (position, normal facing the incoming ray, material).
    float cos_i = -glm::dot(direction, normal);
    if (!(cos_i > 1e-6f)) {  // a shading normal turned past the ray: the face's own normal
      normal = geometric;
      cos_i = std::max(-glm::dot(direction, normal), 1e-6f);
    }
    const Material& m = *material;
    const bool first = path.events == 0;
    // The entry's factors as the hit point sampled its textures; later hits read the factors.
    const SurfaceMaterial* textured = first ? entry_textured : nullptr;
    const float ior = safeIor(m.ior);
    const bool thin = textured ? textured->thin_walled : !(m.thickness > 0.0f);
    const float eta = thin || !inside ? ior : 1.0f / medium_ior;
    const float fresnel = fresnelDielectric(cos_i, eta);
    const float transmitted = transmittedShare(m, textured);
    const vec3 tint = transmissionTint(m, textured);
    const float roughness = clamp01(textured ? textured->roughness : m.roughness);
    const float alpha = roughness * roughness;
    const float spread = alpha * std::min(ior - 1.0f, 2.0f) * 0.5f;
    if (inside && !thin && fresnel >= 1.0f) {  // total internal reflection
      direction = glm::reflect(direction, normal);
      alpha2 += alpha * alpha;
    } else if (inside && !thin) {
      // Leaving: the light that partly reflects inside is followed where it carries a visible
      // share and the budget lasts (a crystal's facets send it out elsewhere), else summed as
      // between parallel walls.
      const vec3 refracted = refractThrough(direction, normal, eta);
      vec3 back, front;
      if (branch_budget > 0 && luminance(throughput) * fresnel >= settings.refraction_branch_weight) {
        const vec3 behind = seenFrom(ibl, position, refracted, lobeWidth(settings, alpha2 + spread * spread));
        followReflected(scene, ibl, settings, position, glm::reflect(direction, normal), throughput * fresnel,
                        alpha2 + alpha * alpha, sigma, medium_ior, behind, branch_budget, path);
        back = vec3(1.0f - fresnel);
        front = vec3(0.0f);
      } else {
        parallelWalls(fresnel, last_absorption, back, front);
      }
      alpha2 += spread * spread;
      path.reflected += throughput * front * transmitted * tint;
      if (transmitted < 1.0f)
        path.resolved +=
            throughput * (back + front) * (1.0f - transmitted) * tint * ibl.irradiance(-normal) / kPi;
      throughput *= back * transmitted * tint;
      direction = refracted;
      inside = false;
    } else {
      // Entering (or crossing a thin wall): the entry's reflection and diffuse are the caller's.
      if (!first) {
        path.reflected += throughput * fresnel;
        if (transmitted < 1.0f)
          path.resolved +=
              throughput * (1.0f - fresnel) * (1.0f - transmitted) * tint * ibl.irradiance(normal) / kPi;
      }
      const vec3 weight = (1.0f - fresnel) * transmitted * tint;
      if (first)
        path.entry = weight;
      else
        throughput *= weight;
      alpha2 += spread * spread;
      if (!thin) {
        direction = refractThrough(direction, normal, eta);
        inside = true;
        medium_ior = ior;
        sigma = absorptionCoefficient(m);
      }
    }
    ++path.events;
    if (alive && first) (*alive)[0] += luminance(path.entry * throughput);
    // From the interface itself, past `offset` (against meeting it again), so a segment's length
    // is the distance between the interfaces.
    const Ray ray{position, direction};
    const RayHit hit = relic.intersect(ray, offset);
    ++path.rays;
    if (!hit.hit()) break;
    if (inside) {
      for (int c = 0; c < 3; ++c) last_absorption[c] = std::exp(-sigma[c] * hit.t);
      throughput *= last_absorption;
    }
    if (path.events >= depth) {  // the cap: what is left goes to the IBL along the last direction
      path.resolved += throughput * seenFrom(ibl, position, direction, lobe());
      path.exit_position = position + direction * offset;
      path.exit_direction = direction;
      path.roughness = lobe();
      return path;
    }
    position = relic.position(ray, hit);
    geometric = hit.geometric_normal;
    normal = relic.shadingNormal(hit, direction);
    material = &scene.relicGltfMaterial(hit, relic);
    if (!isFinite(position) || !isFinite(normal)) break;
    if (alive && path.events < int(alive->size()))
      (*alive)[std::size_t(path.events)] += luminance(path.entry * throughput);
  }
  path.exited = true;
  path.exit_position = position + direction * offset;
  path.exit_direction = direction;
  path.roughness = lobe();
  path.scale = throughput;
  path.environment = seenFrom(ibl, path.exit_position, direction, path.roughness);
  return path;
}

// The weight path.entry of a sample's own entry (traceUnit's first event).
vec3 entryWeight(const vec3& normal, const vec3& direction, const Material& m,
                 const SurfaceMaterial* textured) {
  const float cos_i = std::max(-glm::dot(direction, normal), 1e-6f);
  const float fresnel = fresnelDielectric(cos_i, safeIor(m.ior));
  return (1.0f - fresnel) * transmittedShare(m, textured) * transmissionTint(m, textured);
}

void applyEntry(TransmittedPath& path) {
  path.scale *= path.entry;
  path.resolved *= path.entry;
  path.reflected *= path.entry;
}

}  // namespace

TransmittedPath traceTransmission(const RenderScene& scene, const PrefilteredIbl& ibl,
                                  const TracerSettings& settings, int depth, const vec3& entry_position,
                                  const vec3& entry_normal, const vec3& entry_direction,
                                  const Material& entry, const SurfaceMaterial* entry_textured,
                                  std::vector<double>* alive) {
  TransmittedPath path = traceUnit(scene, ibl, settings, depth, entry_position, entry_normal, entry_direction,
                                   entry, entry_textured, alive);
  applyEntry(path);
  return path;
}

InternalDepth measureInternalDepth(const RenderScene& scene, const PrefilteredIbl& ibl,
                                   const TracerSettings& settings, float residual_limit) {
  InternalDepth result;
  result.left.assign(kMaxInternalDepth + 1, 0.0);
  const Bounds3 box = scene.relicBounds();
  if (box.empty()) return result;
  const vec3 centre = 0.5f * (box.lo + box.hi);
  const float radius = 0.5f * glm::length(box.hi - box.lo);
  const RayScene& relic = scene.relicOnly();
  // Fibonacci sphere of viewing directions, each aimed at a point of a disc across the relic
  // (R2 low-discrepancy offsets): deterministic, even over directions and over the relic.
  constexpr int kProbes = 1024;
  // Traced one event past the largest depth, so the share still inside at that depth is known.
  std::vector<double> alive(kMaxInternalDepth + 1, 0.0);
  for (int i = 0; i < kProbes; ++i) {
    const vec3 dir = fibonacciDirection(i, kProbes);
    const Frame frame(dir);
    const float u = std::fmod(0.5f + 0.7548777f * float(i), 1.0f),
                v = std::fmod(0.5f + 0.5698403f * float(i), 1.0f);
    const float disc_r = 0.8f * radius * std::sqrt(u), phi = 2.0f * kPi * v;
    const vec3 target = centre + disc_r * (std::cos(phi) * frame.t + std::sin(phi) * frame.b);
    const Ray ray{target + 2.0f * radius * dir, -dir};
    const RayHit hit = relic.intersect(ray);
    if (!hit.hit()) continue;
    const Material& m = scene.relicGltfMaterial(hit, relic);
    if (!(m.transmission > 0.0f)) continue;
    ++result.probes_hit;
    traceTransmission(scene, ibl, settings, kMaxInternalDepth + 1, relic.position(ray, hit),
                      relic.shadingNormal(hit, ray.direction), ray.direction, m, nullptr, &alive);
  }
  if (!(alive[0] > 0.0)) return result;
  for (int k = 0; k <= kMaxInternalDepth; ++k) result.left[std::size_t(k)] = alive[std::size_t(k)] / alive[0];
  result.depth = kMaxInternalDepth;
  for (int k = 1; k <= kMaxInternalDepth; ++k)
    if (result.left[std::size_t(k)] < double(residual_limit)) {
      result.depth = k;
      break;
    }
  result.residual = float(result.left[std::size_t(result.depth)]);
  return result;
}

MaterialLayers::MaterialLayers(const RenderScene& scene, const PrefilteredIbl& ibl,
                               const TracerSettings& settings, int internal_depth, bool refraction,
                               bool clearcoat)
    : scene_(scene),
      ibl_(ibl),
      settings_(settings),
      depth_(std::max(internal_depth, 1)),
      refraction_(refraction),
      clearcoat_(clearcoat) {
  // 5% of the hall's mean radiance (its irradiance over the six axes, / pi): darker light shows
  // no contrast after the tone map, whatever the ratio.
  constexpr vec3 kAxes[3] = {vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f)};
  float mean = 0.0f;
  for (const vec3& axis : kAxes) mean += luminance(ibl.irradiance(axis) + ibl.irradiance(-axis));
  dark_ = 0.05f * mean / (6.0f * kPi);
}

bool MaterialLayers::sparkles(const TransmittedPath (&paths)[4], const bool (&transmits)[4]) const {
  const float contrast = settings_.refraction_supersample_contrast;
  if (!(contrast > 0.0f)) return false;
  float lo = 0.0f, hi = 0.0f;
  int n = 0;
  for (int s = 0; s < 4; ++s) {
    if (!transmits[s]) continue;
    const float light = transmittedLight(paths[s]);
    lo = n == 0 ? light : std::min(lo, light);
    hi = n == 0 ? light : std::max(hi, light);
    ++n;
  }
  return n >= 2 && hi + dark_ > contrast * (lo + dark_);
}

std::uint64_t MaterialLayers::supersample(const CameraModel& view, const vec2& centre, const vec2& offset,
                                          const TransmittedPath& own, SupersampledPaths& more) const {
  more.count = 0;
  std::uint64_t rays = 0;
  constexpr int n = SupersampledPaths::kGrid;
  const vec2 quarter(offset.x < 0.0f ? -0.25f : 0.25f, offset.y < 0.0f ? -0.25f : 0.25f);
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const vec2 at = quarter + 0.5f * (vec2(float(gx), float(gy)) + 0.5f) / float(n) - 0.25f;
      HitPoint hp;
      ++rays;
      if (!traceHitPoint(scene_, view, centre + at, hp) || !hp.gltf || !(hp.gltf->transmission > 0.0f))
        continue;
      more.paths[more.count] = traceTransmission(scene_, ibl_, settings_, depth_, hp.position, hp.normal,
                                                 -hp.to_viewer, *hp.gltf, &hp.material);
      rays += more.paths[more.count++].rays;
    }
  if (more.count == 0) more.paths[more.count++] = own;
  return rays;
}

namespace {

// Where a sample may take its anchors' blend (refraction_pass.hpp): the same smooth piece of the
// relic (normals within ~25 degrees, the anchor within ~11 degrees of the sample's tangent
// plane) and the same light inside (exit directions within ~8 degrees; ~2 degrees for an anchor
// blending the coarse lattice's, 4 pixels apart: wider bounds there cost measurable error).
constexpr float kAnchorNormalCos = 0.9f;
constexpr float kAnchorPlaneSine = 0.2f;
constexpr float kAnchorExitCos = 0.99f;
constexpr float kCoarseExitCos = 0.9994f;

// Which sample of pixel p is its anchor: the centre where it was traced, else the first valid
// sub-sample (Full anti-aliasing traces no centres); hits.hits.size() when none is transmissive.
std::size_t anchorSample(const HitPointBuffer& hits, std::size_t p) {
  if (hits.valid[p] && hits.hits[p].gltf && hits.hits[p].gltf->transmissive()) return p;
  if (hits.first_sub[p] == HitPointBuffer::kCentreOnly) return hits.hits.size();
  for (std::size_t i = hits.first_sub[p]; i < hits.first_sub[p] + 4; ++i)
    if (hits.valid[i] && hits.hits[i].gltf && hits.hits[i].gltf->transmissive()) return i;
  return hits.hits.size();
}

// Whether a sample lies on the same smooth piece of the relic as an anchor.
bool sameSurface(const RefractionAnchor& a, const HitPoint& hp) {
  if (a.material != hp.gltf || glm::dot(a.normal, hp.normal) < kAnchorNormalCos) return false;
  const vec3 d = a.position - hp.position;
  return std::abs(glm::dot(d, hp.normal)) <= kAnchorPlaneSine * glm::length(d);
}

// Whether a sample took its anchors' blend, and if not, whether the anchors around it meet other
// events inside (another number of interface events, or one exited and one capped): the path
// changes within a pixel there (a facet's edge, a total internal reflection that starts).
enum class Blend { Blended, NotBlended, EventsDiffer };

// The bilinear blend at image position `at` (pixels, pixel centres at integers) of the anchors
// `step` grid points apart (1: all of them; 2: the coarse lattice of every second one each way),
// per unit of entry, and which anchors it took with which weights (source); where it is not
// Blended the sample must trace its own path.
Blend blendAnchors(const std::vector<RefractionAnchor>& anchors, int grid_width, int grid_height, int stride,
                   int step, const HitPoint& hp, const vec2& at, TransmittedPath& out, WalkSource& source) {
  const vec2 u = at / float(stride * step);
  const vec2 cell = glm::floor(u), f = u - cell;
  const RefractionAnchor* used[4];
  float weights[4];
  std::uint32_t indices[4];
  int n = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const float w = (i ? f.x : 1.0f - f.x) * (j ? f.y : 1.0f - f.y);
      if (!(w > 1e-6f)) continue;
      const int ax = (int(cell.x) + i) * step, ay = (int(cell.y) + j) * step;
      if (ax < 0 || ay < 0 || ax >= grid_width || ay >= grid_height) return Blend::NotBlended;
      const std::size_t index = std::size_t(ay) * std::size_t(grid_width) + std::size_t(ax);
      const RefractionAnchor& a = anchors[index];
      if (!sameSurface(a, hp)) return Blend::NotBlended;
      if (n > 0 && (a.unit.events != used[0]->unit.events || a.unit.exited != used[0]->unit.exited))
        return Blend::EventsDiffer;
      if (n > 0 && glm::dot(a.unit.exit_direction, used[0]->unit.exit_direction) <
                       (step > 1 ? kCoarseExitCos : kAnchorExitCos))
        return Blend::NotBlended;
      used[n] = &a;
      indices[n] = std::uint32_t(index);
      weights[n++] = w;
    }
  if (n == 0) return Blend::NotBlended;
  float total = 0.0f;
  for (int k = 0; k < n; ++k) total += weights[k];
  out = TransmittedPath{};
  vec3 direction(0.0f);
  for (int k = 0; k < n; ++k) {
    const TransmittedPath& a = used[k]->unit;
    const float w = weights[k] / total;
    out.scale += w * a.scale;
    out.resolved += w * a.resolved;
    out.reflected += w * a.reflected;
    out.exit_position += w * a.exit_position;
    direction += w * a.exit_direction;
    out.roughness += w * a.roughness;
  }
  const float length = glm::length(direction);
  if (!(length > 1e-6f)) return Blend::NotBlended;
  out.exit_direction = direction / length;
  out.exited = used[0]->unit.exited;
  out.events = used[0]->unit.events;
  source = WalkSource{};
  source.anchors = std::uint8_t(n);
  for (int k = 0; k < n; ++k) {
    source.anchor[k] = indices[k];
    source.weight[k] = weights[k] / total;
  }
  return Blend::Blended;
}

// The blend of the anchors' walks a blended sample's path took (premultiplied by the mask, so it
// composes as the blend of theirs), where they see the same: no visitor, or the same visitor's
// colour within kWalkAgreement of the brightest; false where the sample walks its own exit ray.
constexpr float kWalkAgreement = 0.1f;

bool blendWalks(const std::vector<ForegroundSample>& anchor_fg, const WalkSource& source,
                ForegroundSample& out) {
  float w_lo = 1.0f, w_hi = 0.0f, l_lo = 0.0f, l_hi = 0.0f;
  vec3 radiance(0.0f);
  float weight = 0.0f;
  for (int a = 0; a < source.anchors; ++a) {
    const ForegroundSample& s = anchor_fg[source.anchor[a]];
    const float l = s.weight * luminance(s.radiance);
    w_lo = std::min(w_lo, s.weight);
    w_hi = std::max(w_hi, s.weight);
    l_lo = a == 0 ? l : std::min(l_lo, l);
    l_hi = a == 0 ? l : std::max(l_hi, l);
    radiance += source.weight[a] * s.weight * s.radiance;
    weight += source.weight[a] * s.weight;
  }
  if (w_hi - w_lo > kWalkAgreement || l_hi - l_lo > kWalkAgreement * l_hi) return false;
  out.weight = weight;
  out.radiance = weight > 0.0f ? radiance / weight : vec3(0.0f);
  return true;
}

// The reflection by the exact Fresnel of the IOR (split-sum's A + B for the rough lobe's own
// loss), in place of the F0 (dielectricF0) the static shading used; a ratio, so an
// interreflection's second scale stays multiplied in. The diffuse keeps 1 - transmission.
void rescaleReflection(const HitPoint& hp, SplitSumShading& sh) {
  const float nv = std::clamp(glm::dot(hp.normal, hp.to_viewer), 1e-4f, 1.0f);
  const SurfaceMaterial& sm = hp.material;
  const float metallic = clamp01(sm.metallic), s = clamp01(sm.specular);
  const vec3 base = glm::clamp(sm.base_colour, vec3(0.0f), vec3(1.0f));
  const vec2 ab = dfg(nv, sm.roughness);
  const vec3 metal = metallic * (base * ab.x + ab.y);
  const vec3 before =
      metal + (1.0f - metallic) * s * (dielectricF0(sm.ior, sm.specular_colour) * ab.x + ab.y);
  const float fresnel = fresnelDielectric(nv, safeIor(hp.gltf->ior));
  const vec3 after = metal + (1.0f - metallic) * s * fresnel * (ab.x + ab.y);
  for (int c = 0; c < 3; ++c)
    sh.specular_scale[c] = before[c] > 0.0f ? sh.specular_scale[c] * after[c] / before[c] : after[c];
  sh.diffuse *= 1.0f - clamp01(sm.transmission);
}

// One path standing for all of a supersampled sample's in the static shading: the mean of their
// weights and of the IBL their exits read, weighted by their scales (the exit rays are each
// walked, walkPaths).
TransmittedPath meanPath(const SupersampledPaths& more) {
  TransmittedPath mean = more.paths[0];
  mean.scale = mean.resolved = mean.reflected = vec3(0.0f);
  vec3 seen(0.0f);
  for (int k = 0; k < more.count; ++k) {
    const TransmittedPath& path = more.paths[k];
    mean.scale += path.scale;
    seen += path.scale * path.environment;
    mean.resolved += path.resolved;
    mean.reflected += path.reflected;
    mean.exited = mean.exited || path.exited;
  }
  const float inv = 1.0f / float(more.count);
  mean.scale *= inv;
  mean.resolved *= inv;
  mean.reflected *= inv;
  for (int c = 0; c < 3; ++c)
    mean.environment[c] = mean.scale[c] > 0.0f ? seen[c] * inv / mean.scale[c] : 0.0f;
  return mean;
}

// The visitors along each of a supersampled sample's exit rays, as one sample the composition
// reads with the mean path's scale: weight 1 where any path sees one, the radiance such that
// scale x radiance is the paths' mean of scale x (the IBL and visitors along its exit ray).
// Returns the rays walked.
std::uint64_t walkPaths(const SupersampledPaths& more, const ForegroundWalk& walk, ForegroundSample& out) {
  vec3 scale(0.0f), seen(0.0f);
  bool visitors = false;
  std::uint64_t walked = 0;
  for (int k = 0; k < more.count; ++k) {
    const TransmittedPath& path = more.paths[k];
    scale += path.scale;
    if (!path.exited || !(luminance(path.scale) > 0.0f)) continue;
    ForegroundSample fg;
    walk.walk(path.exit_position, path.exit_direction, path.exit_direction, path.roughness, fg);
    ++walked;
    const float w = clamp01(fg.weight);
    seen += path.scale * ((1.0f - w) * path.environment + w * fg.radiance);
    visitors = visitors || w > 0.0f;
  }
  out = ForegroundSample{};
  if (!visitors) return walked;
  out.weight = 1.0f;
  for (int c = 0; c < 3; ++c) out.radiance[c] = scale[c] > 0.0f ? seen[c] / scale[c] : 0.0f;
  return walked;
}

}  // namespace

LayerCounts MaterialLayers::shade(const HitPointBuffer& hits, const CameraModel& view,
                                  std::vector<SplitSumShading>& shading, LayerBuffers& buffers) const {
  buffers.layers.resize(hits.hits.size());
  buffers.layered.assign(hits.hits.size(), 0);
  std::atomic<std::uint64_t> rays{0}, refracted{0}, capped{0}, coated{0};
  // The anchors first (refraction_stride > 1): every sample below reads its neighbours'.
  const int stride = refraction_ ? settings_.refraction_stride : 1;
  const int grid_width = stride > 1 ? (hits.width - 1) / stride + 1 : 0;
  const int grid_height = stride > 1 ? (hits.height - 1) / stride + 1 : 0;
  buffers.anchors.assign(std::size_t(grid_width) * std::size_t(grid_height), RefractionAnchor{});
  const std::vector<vec2> pattern = subsamplePattern(4);
  // In two rounds: the coarse lattice's anchors (even grid coordinates) trace their paths; every
  // other anchor takes their blend where they agree as a sample does, else traces its own.
  for (int round = 0; stride > 1 && round < 2; ++round)
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
        [&](const tbb::blocked_range<std::size_t>& r) {
          std::uint64_t local_rays = 0;
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const std::size_t p = hits.covered[k];
            const int x = int(p % std::size_t(hits.width)), y = int(p / std::size_t(hits.width));
            if (x % stride != 0 || y % stride != 0) continue;
            const int gx = x / stride, gy = y / stride;
            if ((gx % 2 == 0 && gy % 2 == 0) != (round == 0)) continue;
            const std::size_t i = anchorSample(hits, p);
            if (i == hits.hits.size()) continue;
            const HitPoint& hp = hits.hits[i];
            RefractionAnchor& a =
                buffers.anchors[std::size_t(gy) * std::size_t(grid_width) + std::size_t(gx)];
            a.position = hp.position;
            a.normal = hp.normal;
            a.material = hp.gltf;
            const vec2 at = vec2(float(x), float(y)) + (i == p ? vec2(0.0f) : pattern[i - hits.first_sub[p]]);
            a.source = WalkSource{};
            if (round == 1 && blendAnchors(buffers.anchors, grid_width, grid_height, stride, 2, hp, at,
                                           a.unit, a.source) == Blend::Blended)
              continue;
            a.unit = traceUnit(scene_, ibl_, settings_, depth_, hp.position, hp.normal, -hp.to_viewer,
                               *hp.gltf, &hp.material, nullptr);
            local_rays += a.unit.rays;
          }
          rays += local_rays;
        });
  buffers.supersampled.clear();
  std::atomic<std::uint64_t> supersampled{0};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, hits.covered.size(), 64),
      [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t local_rays = 0, local_refracted = 0, local_capped = 0, local_coated = 0,
                      local_supersampled = 0;
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const std::size_t p = hits.covered[k];
          const vec2 centre(float(p % std::size_t(hits.width)), float(p / std::size_t(hits.width)));
          const std::size_t first = hits.firstSample(p);
          const int count = hits.sampleCount(p);
          // The path of the first sub-sample that traced its own, shared by the pixel's others on
          // the same surface (refraction_stride > 1); shared_source: where its walk comes from.
          RefractionAnchor shared;
          WalkSource shared_source;
          TransmittedPath paths[4];
          bool transmits[4] = {false, false, false, false};
          for (int s = 0; s < count; ++s) {
            const std::size_t i = first + std::size_t(s);
            if (!hits.valid[i] || hits.hits[i].gltf == nullptr) continue;
            const HitPoint& hp = hits.hits[i];
            if (!(refraction_ && hp.gltf->transmission > 0.0f)) continue;
            transmits[s] = true;
            buffers.layers[i] = SampleLayers{};
            SampleLayers& layer = buffers.layers[i];
            rescaleReflection(hp, shading[i]);
            const vec2 at = centre + (i == p ? vec2(0.0f) : pattern[std::size_t(s)]);
            TransmittedPath& path = paths[s];
            const Blend blend = stride > 1 ? blendAnchors(buffers.anchors, grid_width, grid_height, stride, 1,
                                                          hp, at, path, layer.source)
                                           : Blend::EventsDiffer;
            // Where the anchors meet other events inside, the path changes within the pixel: each
            // sub-sample traces its own there rather than share one.
            const bool blended = blend == Blend::Blended ||
                                 (blend == Blend::NotBlended && shared.material && sameSurface(shared, hp) &&
                                  (path = shared.unit, layer.source = shared_source, true));
            if (blended) {
              path.entry = entryWeight(hp.normal, -hp.to_viewer, *hp.gltf, &hp.material);
              applyEntry(path);
              if (path.exited)
                path.environment = seenFrom(ibl_, path.exit_position, path.exit_direction, path.roughness);
            } else {
              path = traceUnit(scene_, ibl_, settings_, depth_, hp.position, hp.normal, -hp.to_viewer,
                               *hp.gltf, &hp.material, nullptr);
              if (stride > 1 && i != p && !shared.material) {
                shared.position = hp.position;
                shared.normal = hp.normal;
                shared.material = hp.gltf;
                shared.unit = path;
                shared_source.shared = std::int32_t(i);
              }
              applyEntry(path);
              local_rays += path.rays;
            }
          }
          if (count == 4 && sparkles(paths, transmits)) {
            for (int s = 0; s < count; ++s) {
              if (!transmits[s]) continue;
              const std::size_t i = first + std::size_t(s);
              SupersampledPaths more;
              local_rays += supersample(view, centre, pattern[std::size_t(s)], paths[s], more);
              paths[s] = meanPath(more);
              buffers.layers[i].source = WalkSource{};
              buffers.layers[i].source.supersampled =
                  std::int32_t(buffers.supersampled.push_back(more) - buffers.supersampled.begin());
              ++local_supersampled;
            }
          }
          for (int s = 0; s < count; ++s) {
            const std::size_t i = first + std::size_t(s);
            if (!hits.valid[i] || hits.hits[i].gltf == nullptr) continue;
            const HitPoint& hp = hits.hits[i];
            const bool coat = clearcoat_ && hp.gltf->clearcoat > 0.0f;
            if (!transmits[s] && !coat) continue;
            SampleLayers& layer = buffers.layers[i];
            if (!transmits[s]) layer = SampleLayers{};
            SplitSumShading& sh = shading[i];
            if (transmits[s]) {
              const TransmittedPath& path = paths[s];
              ++local_refracted;
              local_capped += path.exited ? 0 : 1;
              sh.diffuse += path.resolved;
              sh.specular_scale += path.reflected;
              layer.transmit_scale = path.scale;
              layer.transmit_environment = path.environment;
              layer.exit_position = path.exit_position;
              layer.exit_direction = path.exit_direction;
              layer.exit_roughness = path.roughness;
              layer.walks = path.exited && luminance(path.scale) > 0.0f;
            }
            if (coat) {
              // The coat's weight and roughness as the hit point sampled them, around its own normal.
              const float weight = clamp01(hp.material.clearcoat);
              const float roughness = clamp01(hp.material.clearcoat_roughness);
              const float coat_nv = std::clamp(glm::dot(hp.clearcoat_normal, hp.to_viewer), 1e-4f, 1.0f);
              const vec2 ab = dfg(coat_nv, roughness);
              layer.coat_scale = vec3(weight * (kDielectricF0 * ab.x + ab.y));
              layer.coat_environment =
                  seenFrom(ibl_, hp.position, glm::reflect(-hp.to_viewer, hp.clearcoat_normal), roughness);
              const float schlick = kDielectricF0 + (1.0f - kDielectricF0) * std::pow(1.0f - coat_nv, 5.0f);
              const float below = 1.0f - weight * schlick;
              sh.specular_scale *= below;
              sh.diffuse *= below;
              layer.transmit_scale *= below;
              ++local_coated;
            }
            buffers.layered[i] = 1;
          }
        }
        rays += local_rays;
        refracted += local_refracted;
        capped += local_capped;
        coated += local_coated;
        supersampled += local_supersampled;
      });
  return {rays.load(), refracted.load(), capped.load(), coated.load(), supersampled.load()};
}

std::uint64_t MaterialLayers::walkTransmitted(const HitPointBuffer& hits, const ForegroundWalk& walk,
                                              LayerBuffers& buffers) const {
  buffers.transmitted_fg.resize(hits.hits.size());
  std::atomic<std::uint64_t> walked{0};
  // The anchors' exit rays first, in two rounds as they were traced: a blended anchor blends the
  // coarse anchors' walks where these agree; a blended sample reads the anchors'.
  buffers.anchor_fg.assign(buffers.anchors.size(), ForegroundSample{});
  for (int round = 0; round < 2; ++round)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buffers.anchors.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::uint64_t local = 0;
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const RefractionAnchor& a = buffers.anchors[k];
                          if (!a.material || !a.unit.exited || (a.source.anchors > 0) != (round == 1))
                            continue;
                          if (round == 1 && blendWalks(buffers.anchor_fg, a.source, buffers.anchor_fg[k]))
                            continue;
                          walk.walk(a.unit.exit_position, a.unit.exit_direction, a.unit.exit_direction,
                                    a.unit.roughness, buffers.anchor_fg[k]);
                          ++local;
                        }
                        walked += local;
                      });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::uint64_t local = 0;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = hits.covered[k];
                        const std::size_t first = hits.firstSample(p);
                        // In sample order: a shared path's owner comes before the sub-samples that share it.
                        for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i) {
                          ForegroundSample& fg = buffers.transmitted_fg[i];
                          fg = ForegroundSample{};
                          if (!hits.valid[i] || !buffers.layered[i] || !buffers.layers[i].walks) continue;
                          const SampleLayers& layer = buffers.layers[i];
                          const WalkSource& source = layer.source;
                          if (source.supersampled >= 0) {
                            local +=
                                walkPaths(buffers.supersampled[std::size_t(source.supersampled)], walk, fg);
                            continue;
                          }
                          if (source.anchors > 0 && blendWalks(buffers.anchor_fg, source, fg)) continue;
                          if (source.shared >= 0) {
                            fg = buffers.transmitted_fg[std::size_t(source.shared)];
                            continue;
                          }
                          walk.walk(layer.exit_position, layer.exit_direction, layer.exit_direction,
                                    layer.exit_roughness, fg);
                          ++local;
                        }
                      }
                      walked += local;
                    });
  return walked;
}

}  // namespace holo::reflect
