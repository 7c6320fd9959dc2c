#include "holo/reflect/relic_visibility.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/error.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::reflect {
namespace {

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// The solid angle of a stratum's lobe over the stratum's own (docs/tracer/self_occlusion.md: 1, 4
// and 9 measured, 4 the lowest error).
constexpr float kStratumOverlap = 4.0f;

float unitFloat(std::uint64_t bits) {
  return float(bits >> 40) / float(1ull << 24);
}

// The diffuse share of the light a surface reflects (what passes the light on to other points).
vec3 diffuseAlbedo(const SurfaceMaterial& m) {
  const vec3 f0 = dielectricF0(m.ior, m.specular_colour) * std::clamp(m.specular, 0.0f, 1.0f);
  return (1.0f - std::clamp(m.metallic, 0.0f, 1.0f)) * (1.0f - std::clamp(m.transmission, 0.0f, 1.0f)) *
         (1.0f - std::min(maxComponent(f0), 1.0f)) * glm::clamp(m.base_colour, vec3(0.0f), vec3(1.0f));
}

}  // namespace

RelicVisibility::RelicVisibility(const RenderScene& scene, const RelicVisibilitySettings& settings)
    : model_(&scene.relic()) {
  const std::string src = "relic visibility";
  side_ = int(std::lround(std::sqrt(double(std::max(settings.rays_per_vertex, 0)))));
  if (side_ * side_ != settings.rays_per_vertex || side_ < 2 || side_ > 16)
    throw InputError(src, "rays_per_vertex", "a square number 4..256",
                     std::to_string(settings.rays_per_vertex));
  if (settings.bounces < 0 || settings.bounces > 8)
    throw InputError(src, "bounces", "0..8", std::to_string(settings.bounces));
  if (!std::isfinite(settings.ray_offset) || settings.ray_offset < 0.0f || settings.ray_offset > 0.1f)
    throw InputError(src, "ray_offset", "0..0.1 metres", std::to_string(settings.ray_offset));
  if (!std::isfinite(settings.lattice_steps_per_relic) || settings.lattice_steps_per_relic < 0.0f ||
      settings.lattice_steps_per_relic > 64.0f)
    throw InputError(src, "lattice_steps_per_relic", "0..64",
                     std::to_string(settings.lattice_steps_per_relic));
  ray_offset_ = settings.ray_offset;

  const Model& model = scene.relic();
  const RayScene& relic = scene.relicOnly();
  const int n = settings.rays_per_vertex;
  const Bounds3 relic_box = model.bounds();
  transfers_.resize(model.meshes.size());
  normals_.resize(model.meshes.size());
  positions_.resize(model.meshes.size());
  lattices_.resize(model.meshes.size());
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const TriangleMesh& mesh = model.meshes[m];
    if (mesh.triangles.empty()) continue;
    if (mesh.normals.size() == mesh.positions.size()) {
      normals_[m] = mesh.normals;
    } else {
      TriangleMesh copy = mesh;
      copy.computeNormals();
      normals_[m] = copy.normals;
    }
    for (vec3& normal : normals_[m]) {
      const float len = glm::length(normal);
      normal = len > 1e-12f && std::isfinite(len) ? normal / len : vec3(0.0f);
    }
    addLattices(m, relic_box, settings.lattice_steps_per_relic);
    const int material = mesh.material;
    const bool two_sided = material >= 0 && std::size_t(material) < model.materials.size() &&
                           (model.materials[std::size_t(material)].double_sided ||
                            model.materials[std::size_t(material)].transmission > 0.0f);
    for (std::uint32_t s = 0; s < (two_sided ? 2u : 1u); ++s) {
      transfers_[m][s].resize(positions_[m].size());
      for (std::uint32_t v = 0; v < positions_[m].size(); ++v)
        vertex_sides_list_.push_back({std::uint32_t(m), v, s});
    }
  }
  const std::vector<VertexSide>& jobs = vertex_sides_list_;
  vertex_sides_ = jobs.size();

  // Pass 0: the open directions' clamped cosine; pass b: plus the bounce off the transfers of
  // pass b - 1.
  std::vector<std::array<std::vector<Transfer>, 2>> previous;
  std::atomic<std::uint64_t> rays{0};
  for (int pass = 0; pass <= settings.bounces; ++pass) {
    if (pass > 0) previous = transfers_;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, jobs.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
          std::uint64_t cast = 0;
          for (std::size_t j = r.begin(); j < r.end(); ++j) {
            const VertexSide& job = jobs[j];
            const vec3 normal = (job.side == 0 ? 1.0f : -1.0f) * normals_[job.mesh][job.vertex];
            Transfer out;
            if (!(glm::length(normal) > 0.5f)) {
              transfers_[job.mesh][job.side][job.vertex] = out;  // no hemisphere: nothing reaches it
              continue;
            }
            const auto y = IrradianceSH::basis(normal);
            for (int i = 0; i < 9; ++i) out.whole[i] = vec3(IrradianceSH::kCosineLobe[i] * y[i]);
            int occluded = 0;
            for (int k = 0; k < n; ++k) {
              const Ray ray = this->ray(job, k);
              const RayHit hit = relic.intersect(ray);
              ++cast;
              // Glass passes the light on (its tint and bending left out) rather than shadowing.
              if (!hit.hit() || scene.relicGltfMaterial(hit, relic).transmissive()) {
                out.open_strata[std::size_t(k / 64)] |= std::uint64_t(1) << (k % 64);
                continue;
              }
              ++occluded;
              const auto yw = IrradianceSH::basis(ray.direction);
              for (int i = 0; i < 9; ++i) out.whole[i] -= vec3(kPi / float(n) * yw[i]);
              if (pass == 0) continue;
              const SurfacePoint s = resolveSurface(scene, relic, ray, hit, 0.0f);
              const vec3 albedo = diffuseAlbedo(s.material) * s.occlusion;
              if (!(maxComponent(albedo) > 0.0f) || !s.location.located()) continue;
              const auto& sides = previous[s.location.mesh];
              const auto& values = sides[s.location.front || sides[1].empty() ? 0 : 1];
              if (values.empty()) continue;
              const Corners c = corners(s.location);
              for (int i = 0; i < 9; ++i)
                out.bounce[i] +=
                    albedo / float(n) *
                    (c.weight[0] * values[c.vertex.x].whole[i] + c.weight[1] * values[c.vertex.y].whole[i] +
                     c.weight[2] * values[c.vertex.z].whole[i]);
            }
            for (int i = 0; i < 9; ++i) out.whole[i] += out.bounce[i];
            out.open = 1.0f - float(occluded) / float(n);
            transfers_[job.mesh][job.side][job.vertex] = out;
          }
          rays += cast;
        });
  }
  rays_ = rays.load();
  double sum = 0.0;
  for (const VertexSide& job : jobs) {
    const float occlusion = 1.0f - transfers_[job.mesh][job.side][job.vertex].open;
    max_occlusion_ = std::max(max_occlusion_, occlusion);
    sum += double(occlusion);
  }
  mean_occlusion_ = jobs.empty() ? 0.0f : float(sum / double(jobs.size()));
}

Ray RelicVisibility::ray(const VertexSide& v, int k) const {
  const vec3 normal = (v.side == 0 ? 1.0f : -1.0f) * normals_[v.mesh][v.vertex];
  const std::uint64_t key = mix((std::uint64_t(v.mesh) << 40) ^ (std::uint64_t(v.vertex) << 1) ^ v.side);
  const float jx = unitFloat(mix(key ^ std::uint64_t(2 * k))),
              jy = unitFloat(mix(key ^ std::uint64_t(2 * k + 1)));
  const float u1 = (float(k % side_) + jx) / float(side_), u2 = (float(k / side_) + jy) / float(side_);
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  const Frame frame(normal);
  const vec3 origin = positions_[v.mesh][v.vertex] + ray_offset_ * normal;
  return {origin,
          frame.toWorld(vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(1.0f - u1, 0.0f))))};
}

RelicVisibility::Lighting RelicVisibility::lit(const PrefilteredIbl& ibl, bool filtered,
                                               bool without_sun) const {
  Lighting lighting;
  lighting.without_sun = without_sun && ibl.sun().found;
  const std::array<vec3, 9> sun = ibl.relicFrameSunRadiance();
  lighting.irradiance.resize(transfers_.size());
  for (std::size_t m = 0; m < transfers_.size(); ++m)
    for (int s = 0; s < 2; ++s)
      lighting.irradiance[m][std::size_t(s)].resize(transfers_[m][std::size_t(s)].size());
  const std::array<vec3, 9> radiance = ibl.relicFrameRadiance();
  const int n = side_ * side_;
  const std::vector<VertexSide>& jobs = vertex_sides_list_;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, jobs.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t j = r.begin(); j < r.end(); ++j) {
          const VertexSide& v = jobs[j];
          const Transfer& t = transfers_[v.mesh][v.side][v.vertex];
          vec3 e(0.0f);
          for (int i = 0; i < 9; ++i) e += (filtered ? t.bounce[i] : t.whole[i]) * radiance[i];
          if (lighting.without_sun && !filtered)
            for (int i = 0; i < 9; ++i) e -= (t.whole[i] - t.bounce[i]) * sun[i];
          const vec3 normal = (v.side == 0 ? 1.0f : -1.0f) * normals_[v.mesh][v.vertex];
          for (int k = 0; filtered && k < n; ++k) {
            if (!(t.open_strata[std::size_t(k / 64)] >> (k % 64) & 1u)) continue;
            const Ray ray = this->ray(v, k);
            // The stratum's solid angle, 1 / (N pdf) with pdf = cos / pi, read as a GGX lobe about the
            // reflected direction (4 pi alpha^2) kStratumOverlap times as large: neighbouring strata's
            // lobes overlap, so a small bright light does not flicker between vertices as it falls in
            // one stratum or the next.
            const float cosine = std::max(glm::dot(ray.direction, normal), 1e-3f);
            const float alpha = std::sqrt(kStratumOverlap * kPi / (float(n) * cosine) / (4.0f * kPi));
            const float roughness = std::min(std::sqrt(alpha), 1.0f);
            vec3 seen = ibl.seenFrom(ray.origin, ray.direction, roughness);
            if (lighting.without_sun)
              seen = glm::max(seen - ibl.sunSeenFrom(ray.origin, ray.direction, roughness), vec3(0.0f));
            e += kPi / float(n) * seen;
          }
          lighting.irradiance[v.mesh][v.side][v.vertex] = isFinite(e) ? glm::max(e, vec3(0.0f)) : vec3(0.0f);
        }
      });
  return lighting;
}

float RelicVisibility::largestDisplayedChange(const Lighting& lighting, const PrefilteredIbl& ibl,
                                              float exposure) const {
  std::vector<vec3> albedo(model_->meshes.size());
  for (std::size_t m = 0; m < albedo.size(); ++m) {
    const std::size_t material = std::size_t(std::max(model_->meshes[m].material, 0));
    if (material >= model_->materials.size()) continue;
    const Material& mat = model_->materials[material];
    SurfaceMaterial factors;
    factors.base_colour = mat.base_colour;
    factors.metallic = mat.metallic;
    factors.specular = mat.specular;
    factors.specular_colour = mat.specular_colour;
    factors.transmission = mat.transmission;
    factors.ior = mat.ior;
    albedo[m] = diffuseAlbedo(factors) / kPi;
  }
  if (!(exposure > 0.0f)) {  // autoExposure over the vertices: the log-average luminance to 0.18
    double log_sum = 0.0;
    std::size_t count = 0;
    for (const VertexSide& v : vertex_sides_list_) {
      const float l = luminance(albedo[v.mesh] * lighting.irradiance[v.mesh][v.side][v.vertex]);
      if (!(l > 0.0f)) continue;
      log_sum += std::log(double(l));
      ++count;
    }
    exposure = count == 0 ? 1.0f : float(0.18 / std::exp(log_sum / double(count)));
  }
  float largest = 0.0f;
  for (const VertexSide& v : vertex_sides_list_) {
    const vec3 normal = (v.side == 0 ? 1.0f : -1.0f) * normals_[v.mesh][v.vertex];
    if (!(glm::length(normal) > 0.5f)) continue;
    const vec3 lit = toneMapCodes(albedo[v.mesh] * lighting.irradiance[v.mesh][v.side][v.vertex], exposure);
    const vec3 open = toneMapCodes(
        albedo[v.mesh] * (lighting.without_sun ? ibl.irradianceWithoutSun(normal) : ibl.irradiance(normal)),
        exposure);
    largest = std::max(largest, maxComponent(glm::abs(lit - open)));
  }
  return largest;
}

bool RelicVisibility::covers(const SurfaceLocation& at) const {
  if (!at.located() || at.mesh >= transfers_.size()) return false;
  return !transfers_[at.mesh][at.front ? 0 : 1].empty();
}

void RelicVisibility::addLattices(std::size_t m, const Bounds3& relic_box, float steps_per_relic) {
  const TriangleMesh& mesh = model_->meshes[m];
  positions_[m] = mesh.positions;
  if (!(steps_per_relic > 0.0f)) return;
  const float spacing = glm::length(relic_box.hi - relic_box.lo) / steps_per_relic;
  if (!(spacing > 0.0f) || !std::isfinite(spacing)) return;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uvec3 tri = mesh.triangles[t];
    const vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
    const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const int steps = std::min(int(std::ceil(longest / spacing)), kMaxLatticeSteps);
    if (!(steps >= 2)) continue;
    if (lattices_[m].empty()) lattices_[m].resize(mesh.triangles.size());
    lattices_[m][t] = {std::uint32_t(positions_[m].size()), steps};
    const vec3 na = normals_[m][tri.x], nb = normals_[m][tri.y], nc = normals_[m][tri.z];
    for (int j = 0; j <= steps; ++j)
      for (int i = 0; i + j <= steps; ++i) {
        const float u = float(i) / float(steps), v = float(j) / float(steps);
        positions_[m].push_back((1.0f - u - v) * a + u * b + v * c);
        const vec3 normal = (1.0f - u - v) * na + u * nb + v * nc;
        const float len = glm::length(normal);
        normals_[m].push_back(len > 1e-12f && std::isfinite(len) ? normal / len : vec3(0.0f));
      }
  }
}

RelicVisibility::Corners RelicVisibility::corners(const SurfaceLocation& at) const {
  const float u = at.barycentric.x, v = at.barycentric.y;
  const std::vector<Lattice>& lattices = lattices_[at.mesh];
  if (lattices.empty() || lattices[at.triangle].steps == 0)
    return {model_->meshes[at.mesh].triangles[at.triangle], {1.0f - u - v, u, v}};
  // The lattice's cell holding (u, v): point (i, j) at u = i / steps, v = j / steps, row j after
  // the rows below it (steps + 1 - r points each).
  const Lattice& lattice = lattices[at.triangle];
  const int n = lattice.steps;
  const auto index = [&](int i, int j) {
    return lattice.first + std::uint32_t(j * (n + 1) - j * (j - 1) / 2 + i);
  };
  const float fu = std::clamp(u, 0.0f, 1.0f) * float(n), fv = std::clamp(v, 0.0f, 1.0f) * float(n);
  const int i = std::clamp(int(fu), 0, n - 1), j = std::clamp(int(fv), 0, n - 1 - i);
  const float a = fu - float(i), b = fv - float(j);
  if (a + b <= 1.0f || i + j >= n - 1) {
    const float wa = std::clamp(a, 0.0f, 1.0f), wb = std::clamp(b, 0.0f, 1.0f - wa);
    return {uvec3(index(i, j), index(i + 1, j), index(i, j + 1)), {1.0f - wa - wb, wa, wb}};
  }
  return {uvec3(index(i + 1, j + 1), index(i, j + 1), index(i + 1, j)), {a + b - 1.0f, 1.0f - a, 1.0f - b}};
}

vec3 RelicVisibility::irradiance(const Lighting& lighting, const SurfaceLocation& at) const {
  const Corners c = corners(at);
  const std::vector<vec3>& e = lighting.irradiance[at.mesh][at.front ? 0 : 1];
  return c.weight[0] * e[c.vertex.x] + c.weight[1] * e[c.vertex.y] + c.weight[2] * e[c.vertex.z];
}

float RelicVisibility::openness(const SurfaceLocation& at) const {
  const Corners c = corners(at);
  const auto& values = transfers_[at.mesh][at.front ? 0 : 1];
  return std::clamp(c.weight[0] * values[c.vertex.x].open + c.weight[1] * values[c.vertex.y].open +
                        c.weight[2] * values[c.vertex.z].open,
                    0.0f, 1.0f);
}

}  // namespace holo::reflect
