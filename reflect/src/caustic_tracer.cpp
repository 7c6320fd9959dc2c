#include "holo/reflect/caustic_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "environment_directions.hpp"
#include "holo/core/stats.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/transmissive_relic.hpp"

namespace holo::reflect {

namespace {

std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform numbers in [0, 1) for one photon.
class PhotonRandom {
 public:
  PhotonRandom(std::uint64_t seed, std::uint64_t photon)
      : state_(mix64(seed * 0x2545f4914f6cdd1dull ^ photon)) {}
  float next() {
    state_ = mix64(state_);
    return float(state_ >> 40) * (1.0f / 16777216.0f);
  }
  vec2 next2D() { return {next(), next()}; }

 private:
  std::uint64_t state_;
};

struct Emitted {
  Ray ray;
  vec3 flux{0.0f};  // W per RGB channel
};

// Unit vectors u, v with (u, v, n) orthonormal.
void frameAround(const vec3& n, vec3& u, vec3& v) {
  u = glm::normalize(std::abs(n.y) < 0.9f ? glm::cross(n, vec3(0.0f, 1.0f, 0.0f))
                                          : glm::cross(n, vec3(1.0f, 0.0f, 0.0f)));
  v = glm::cross(n, u);
}

struct BoundingSphere {
  vec3 centre{0.0f};
  float radius = 0.0f;
};
BoundingSphere boundingSphereOf(const Bounds3& b) {
  return {b.center(), 0.5f * glm::length(b.extent()) * 1.001f};
}

// The winding normal of the hit's triangle: the side a photon arrives from decides entering.
vec3 windingNormal(const RenderScene& scene, const RayHit& hit) {
  const TriangleMesh& mesh = scene.relic().meshes[scene.relicMesh(hit, scene.relicOnly())];
  const uvec3 t = mesh.triangles.at(hit.primitive);
  return glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
}

// Follows one photon through the relic; the receiver's cell and flux when it lands there.
bool followPhoton(const RenderScene& scene, const CausticReceiverGrid& grid, int max_events, float offset,
                  Emitted photon, PhotonRandom& random, int& cell, vec3& flux) {
  const RayScene& relic = scene.relicOnly();
  Ray ray = photon.ray;
  vec3 power = photon.flux;
  bool in_volume = false;
  vec3 absorption(0.0f);
  int events = 0;
  for (;;) {
    const RayHit hit = relic.intersect(ray, events == 0 ? 0.0f : offset);
    const float t_receiver = ray.direction.y < 0.0f ? (grid.height - ray.origin.y) / ray.direction.y : -1.0f;
    if (!hit.hit() || (t_receiver > 0.0f && t_receiver < hit.t)) {
      if (events == 0 || in_volume || t_receiver <= 0.0f) return false;
      const vec3 p = ray.origin + t_receiver * ray.direction;
      const vec2 q = (vec2(p.x, p.z) - grid.centre + grid.half_size) / grid.cellSize();
      const int x = int(std::floor(q.x)), z = int(std::floor(q.y));
      if (x < 0 || z < 0 || x >= grid.resolution || z >= grid.resolution || !isFinite(power)) return false;
      cell = z * grid.resolution + x;
      flux = power;
      return true;
    }
    if (in_volume) power *= transmittance(absorption, hit.t);
    if (events == max_events) return false;
    ++events;
    const SurfacePoint s = resolveSurface(scene, relic, ray, hit, 0.0f);
    if (!isFinite(s.normal) || !isFinite(s.position)) return false;
    const bool entering = glm::dot(windingNormal(scene, hit), ray.direction) < 0.0f;
    const SurfaceMaterial& m = s.material;
    // The shading normal on the side the photon comes from.
    vec3 n = s.normal;
    if (glm::dot(n, ray.direction) > 0.0f) n = -n;
    const float cos_i = std::clamp(-glm::dot(ray.direction, n), 0.0f, 1.0f);
    const float eta = m.thin_walled ? 1.0f : (entering ? m.ior : 1.0f / std::max(m.ior, 1.0f));
    const float fresnel = fresnelDielectric(cos_i, entering || m.thin_walled ? m.ior : eta);
    vec3 direction;
    bool reflected = false;
    if (random.next() < fresnel) {
      reflected = true;
      direction = glm::reflect(ray.direction, n);
      // The dielectric's reflection; a metal reflects its base colour instead.
      power *= glm::mix(vec3(1.0f), m.base_colour, m.metallic);
    } else {
      // What is not reflected: transmitted (1 - metallic) transmission base_colour where it
      // enters, passed on unweighted where it leaves; the rest (diffuse, metal) ends here.
      if (entering || m.thin_walled) power *= (1.0f - m.metallic) * m.transmission * m.base_colour;
      if (!(power.x > 0.0f || power.y > 0.0f || power.z > 0.0f)) return false;
      direction = m.thin_walled ? ray.direction : refractIncident(ray.direction, n, eta);
    }
    if (!reflected && !m.thin_walled) {
      in_volume = entering;
      absorption =
          in_volume ? attenuationCoefficient(m.attenuation_colour, m.attenuation_distance) : vec3(0.0f);
    }
    const vec3 side =
        glm::dot(direction, s.geometric_normal) >= 0.0f ? s.geometric_normal : -s.geometric_normal;
    ray = Ray{s.position + offset * side, glm::normalize(direction)};
  }
}

// Launches photons [0, settings.photons) from `emit` and bins them on the grid.
CausticImage traceAndBin(const RenderScene& scene, const CausticReceiverGrid& grid,
                         const CausticTracerSettings& settings,
                         const std::function<bool(std::uint64_t, PhotonRandom&, Emitted&)>& emit) {
  const Stopwatch watch;
  CausticImage image;
  image.grid = grid;
  image.traced = settings.photons;
  const int res = std::max(1, grid.resolution);
  image.grid.resolution = res;
  const std::size_t cells = std::size_t(res) * std::size_t(res);
  const Bounds3 bounds = scene.relicBounds();
  const float offset = 1e-5f * std::max(1e-3f, glm::length(bounds.extent()));
  constexpr std::uint64_t kBatch = 16384;
  const std::uint64_t batches = (settings.photons + kBatch - 1) / kBatch;
  std::vector<std::vector<std::pair<int, vec3>>> landed(batches);
  tbb::parallel_for(std::uint64_t(0), batches, [&](std::uint64_t b) {
    const std::uint64_t begin = b * kBatch, end = std::min(settings.photons, begin + kBatch);
    for (std::uint64_t i = begin; i < end; ++i) {
      PhotonRandom random(settings.seed, i);
      Emitted photon;
      if (!emit(i, random, photon)) continue;
      int cell = 0;
      vec3 flux(0.0f);
      if (followPhoton(scene, image.grid, settings.max_events, offset, photon, random, cell, flux))
        landed[b].emplace_back(cell, flux);
    }
  });
  std::vector<glm::dvec3> power(cells, glm::dvec3(0.0));
  for (const auto& batch : landed) {
    image.stored += batch.size();
    for (const auto& [cell, flux] : batch) power[std::size_t(cell)] += glm::dvec3(flux);
  }
  const double area = double(image.grid.cellSize()) * double(image.grid.cellSize());
  cv::Mat binned(res, res, CV_32FC3);
  for (int z = 0; z < res; ++z)
    for (int x = 0; x < res; ++x) {
      const glm::dvec3 e = power[std::size_t(z) * std::size_t(res) + std::size_t(x)] / area;
      binned.at<cv::Vec3f>(z, x) = cv::Vec3f(float(e.z), float(e.y), float(e.x));
    }
  if (settings.smoothing_cells > 0) {
    const int r = settings.smoothing_cells;
    cv::Mat kernel(1, 2 * r + 1, CV_32F);
    float sum = 0.0f;
    for (int k = -r; k <= r; ++k) sum += kernel.at<float>(0, k + r) = float(r + 1 - std::abs(k));
    kernel /= sum;
    // Zero beyond the square: the light that lands there is not the receiver's.
    cv::sepFilter2D(binned, image.irradiance, CV_32F, kernel, kernel, cv::Point(-1, -1), 0.0,
                    cv::BORDER_CONSTANT);
  } else {
    image.irradiance = binned;
  }
  static auto& traced = stats::counter("Caustics/Live photons traced");
  static auto& stored = stats::counter("Caustics/Live photons stored");
  traced.fetch_add(std::int64_t(image.traced), std::memory_order_relaxed);
  stored.fetch_add(std::int64_t(image.stored), std::memory_order_relaxed);
  image.ms = watch.ms();
  return image;
}

}  // namespace

bool modelTransmits(const Model& model) {
  for (const TriangleMesh& mesh : model.meshes) {
    const auto m = static_cast<std::size_t>(mesh.material);
    if (mesh.material >= 0 && m < model.materials.size() && model.materials[m].transmissive()) return true;
  }
  return false;
}

bool relicTransmits(const RenderScene& scene) {
  if (const auto& m = scene.relicMaterialOverride()) return m->transmission > 0.0f;
  return modelTransmits(scene.relic());
}

CausticImage tracePointCaustics(const RenderScene& scene, const vec3& light_position, const vec3& light_power,
                                const CausticReceiverGrid& grid, const CausticTracerSettings& settings) {
  const BoundingSphere bound = boundingSphereOf(scene.relicBounds());
  const vec3 to_relic = bound.centre - light_position;
  const float distance = glm::length(to_relic);
  const bool inside = distance <= bound.radius;
  const float cos_max =
      inside ? -1.0f : std::sqrt(std::max(0.0f, 1.0f - bound.radius * bound.radius / (distance * distance)));
  const vec3 axis = inside ? vec3(0.0f, -1.0f, 0.0f) : to_relic / distance;
  vec3 u, v;
  frameAround(axis, u, v);
  const vec3 flux =
      light_power * (0.5f * (1.0f - cos_max)) / float(std::max<std::uint64_t>(1, settings.photons));
  return traceAndBin(scene, grid, settings, [&](std::uint64_t, PhotonRandom& random, Emitted& out) {
    const vec2 r = random.next2D();
    const float cos_theta = 1.0f - r.x * (1.0f - cos_max);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * r.y;
    out.ray = Ray{light_position,
                  glm::normalize(sin_theta * (std::cos(phi) * u + std::sin(phi) * v) + cos_theta * axis)};
    out.flux = flux;
    return true;
  });
}

namespace {

// A photon from the hall direction `towards_light` (unit, pointing away from the relic) of
// radiance L drawn with density pdf (per steradian): it crosses a disc across the relic's bounding
// sphere, perpendicular to its travel, carrying L pi r^2 / (pdf N).
Emitted photonThroughDisc(const BoundingSphere& bound, const vec3& towards_light, const vec3& radiance,
                          double pdf, double photons, PhotonRandom& random) {
  const vec3 travel = -glm::normalize(towards_light);
  vec3 u, v;
  frameAround(travel, u, v);
  const vec2 r = random.next2D();
  const float radius = bound.radius * std::sqrt(r.x), phi = 2.0f * kPi * r.y;
  const double disc = double(kPi) * double(bound.radius) * double(bound.radius);
  Emitted out;
  out.ray = Ray{
      bound.centre - 2.0f * bound.radius * travel + radius * (std::cos(phi) * u + std::sin(phi) * v), travel};
  out.flux = radiance * float(disc / (pdf * photons));
  return out;
}

}  // namespace

CausticImage traceEnvironmentCaustics(const RenderScene& scene, const PrefilteredIbl& ibl,
                                      const CausticReceiverGrid& grid,
                                      const CausticTracerSettings& settings) {
  const EnvironmentDirections directions(ibl.level(0));
  const BoundingSphere bound = boundingSphereOf(scene.relicBounds());
  const float c = std::cos(ibl.relicTurn()), s = std::sin(ibl.relicTurn());
  const double photons = double(std::max<std::uint64_t>(1, settings.photons));
  if (directions.empty()) {
    CausticTracerSettings none = settings;
    none.photons = 0;
    return traceAndBin(scene, grid, none, [](std::uint64_t, PhotonRandom&, Emitted&) { return false; });
  }
  return traceAndBin(scene, grid, settings, [&](std::uint64_t, PhotonRandom& random, Emitted& out) {
    const EnvironmentDirections::Sample pick = directions.sample(random.next2D());
    if (!(pick.pdf > 0.0)) return false;
    const vec3& hall = pick.direction;
    // The hall direction in the relic's frame: PrefilteredIbl::turnDirection inverted.
    const vec3 towards_light(c * hall.x - s * hall.z, hall.y, s * hall.x + c * hall.z);
    out = photonThroughDisc(bound, towards_light, pick.radiance, pick.pdf, photons, random);
    return true;
  });
}

CausticImage traceEnvironmentCaustics(const RenderScene& scene, const Environment& environment,
                                      const CausticReceiverGrid& grid,
                                      const CausticTracerSettings& settings) {
  const BoundingSphere bound = boundingSphereOf(scene.relicBounds());
  const double photons = double(std::max<std::uint64_t>(1, settings.photons));
  CausticTracerSettings run = settings;
  if (environment.black()) run.photons = 0;
  return traceAndBin(scene, grid, run, [&](std::uint64_t, PhotonRandom& random, Emitted& out) {
    const EnvironmentSample pick = environment.sample(random.next2D());
    if (!(pick.pdf > 0.0f)) return false;
    out = photonThroughDisc(bound, pick.direction, pick.radiance, double(pick.pdf), photons, random);
    return true;
  });
}

}  // namespace holo::reflect
