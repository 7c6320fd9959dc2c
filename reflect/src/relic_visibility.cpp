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

namespace holo::reflect {
namespace {

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

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
  const int side = int(std::lround(std::sqrt(double(std::max(settings.rays_per_vertex, 0)))));
  if (side * side != settings.rays_per_vertex || side < 2 || side > 64)
    throw InputError(src, "rays_per_vertex", "a square number 4..4096",
                     std::to_string(settings.rays_per_vertex));
  if (settings.bounces < 0 || settings.bounces > 8)
    throw InputError(src, "bounces", "0..8", std::to_string(settings.bounces));
  if (!std::isfinite(settings.ray_offset) || settings.ray_offset < 0.0f || settings.ray_offset > 0.1f)
    throw InputError(src, "ray_offset", "0..0.1 metres", std::to_string(settings.ray_offset));

  const Model& model = scene.relic();
  const RayScene& relic = scene.relicOnly();
  const int n = settings.rays_per_vertex;
  transfers_.resize(model.meshes.size());
  // Per mesh, its vertex normals (computed from the faces where the mesh has none).
  std::vector<std::vector<vec3>> normals(model.meshes.size());
  struct Job {
    std::uint32_t mesh, vertex, side;
  };
  std::vector<Job> jobs;
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const TriangleMesh& mesh = model.meshes[m];
    if (mesh.triangles.empty()) continue;
    if (mesh.normals.size() == mesh.positions.size()) {
      normals[m] = mesh.normals;
    } else {
      TriangleMesh copy = mesh;
      copy.computeNormals();
      normals[m] = copy.normals;
    }
    for (vec3& normal : normals[m]) {
      const float len = glm::length(normal);
      normal = len > 1e-12f && std::isfinite(len) ? normal / len : vec3(0.0f);
    }
    const int material = mesh.material;
    const bool two_sided = material >= 0 && std::size_t(material) < model.materials.size() &&
                           (model.materials[std::size_t(material)].double_sided ||
                            model.materials[std::size_t(material)].transmission > 0.0f);
    for (std::uint32_t s = 0; s < (two_sided ? 2u : 1u); ++s) {
      transfers_[m][s].resize(mesh.positions.size());
      for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) jobs.push_back({std::uint32_t(m), v, s});
    }
  }
  vertex_sides_ = jobs.size();

  // The k-th ray of a vertex side: stratum (k % side, k / side) of the cosine-distributed
  // hemisphere, its offset within the stratum hashed from the vertex side.
  const auto rayOf = [&](const Job& job, int k) {
    const vec3 normal = (job.side == 0 ? 1.0f : -1.0f) * normals[job.mesh][job.vertex];
    const std::uint64_t key =
        mix((std::uint64_t(job.mesh) << 40) ^ (std::uint64_t(job.vertex) << 1) ^ job.side);
    const float jx = unitFloat(mix(key ^ std::uint64_t(2 * k))),
                jy = unitFloat(mix(key ^ std::uint64_t(2 * k + 1)));
    const float u1 = (float(k % side) + jx) / float(side), u2 = (float(k / side) + jy) / float(side);
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    const Frame frame(normal);
    const vec3 origin = model.meshes[job.mesh].positions[job.vertex] + settings.ray_offset * normal;
    return Ray{origin, frame.toWorld(
                           vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(1.0f - u1, 0.0f))))};
  };

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
            const Job& job = jobs[j];
            const vec3 normal = (job.side == 0 ? 1.0f : -1.0f) * normals[job.mesh][job.vertex];
            Transfer out;
            if (!isFinite(normal) || !(glm::length(normal) > 0.5f)) {
              transfers_[job.mesh][job.side][job.vertex] = out;  // no hemisphere: left unoccluded, black
              continue;
            }
            const auto y = IrradianceSH::basis(normal);
            for (int i = 0; i < 9; ++i) out.t[i] = vec3(IrradianceSH::kCosineLobe[i] * y[i]);
            int occluded = 0;
            for (int k = 0; k < n; ++k) {
              const Ray ray = rayOf(job, k);
              const RayHit hit = relic.intersect(ray);
              ++cast;
              if (!hit.hit()) continue;
              ++occluded;
              const auto yw = IrradianceSH::basis(ray.direction);
              for (int i = 0; i < 9; ++i) out.t[i] -= vec3(kPi / float(n) * yw[i]);
              if (pass == 0) continue;
              const SurfacePoint s = resolveSurface(scene, relic, ray, hit, 0.0f);
              const vec3 albedo = diffuseAlbedo(s.material) * s.occlusion;
              if (!(maxComponent(albedo) > 0.0f) || !s.location.located()) continue;
              const auto& sides = previous[s.location.mesh];
              const auto& values = sides[s.location.front || sides[1].empty() ? 0 : 1];
              if (values.empty()) continue;
              const uvec3 tri = model.meshes[s.location.mesh].triangles[s.location.triangle];
              const float u = s.location.barycentric.x, v = s.location.barycentric.y;
              for (int i = 0; i < 9; ++i)
                out.t[i] +=
                    albedo / float(n) *
                    ((1.0f - u - v) * values[tri.x].t[i] + u * values[tri.y].t[i] + v * values[tri.z].t[i]);
            }
            out.open = 1.0f - float(occluded) / float(n);
            transfers_[job.mesh][job.side][job.vertex] = out;
          }
          rays += cast;
        });
  }
  rays_ = rays.load();
  double sum = 0.0;
  for (const Job& job : jobs) {
    const float occlusion = 1.0f - transfers_[job.mesh][job.side][job.vertex].open;
    max_occlusion_ = std::max(max_occlusion_, occlusion);
    sum += double(occlusion);
  }
  mean_occlusion_ = jobs.empty() ? 0.0f : float(sum / double(jobs.size()));
}

bool RelicVisibility::covers(const SurfaceLocation& at) const {
  if (!at.located() || at.mesh >= transfers_.size()) return false;
  const auto& sides = transfers_[at.mesh];
  return !sides[at.front ? 0 : 1].empty();
}

RelicVisibility::Corners RelicVisibility::corners(const SurfaceLocation& at) const {
  const auto& values = transfers_[at.mesh][at.front ? 0 : 1];
  const uvec3 tri = model_->meshes[at.mesh].triangles[at.triangle];
  const float u = at.barycentric.x, v = at.barycentric.y;
  return {{&values[tri.x], &values[tri.y], &values[tri.z]}, {1.0f - u - v, u, v}};
}

vec3 RelicVisibility::irradiance(const SurfaceLocation& at, const std::array<vec3, 9>& radiance) const {
  const Corners c = corners(at);
  vec3 e(0.0f);
  for (int i = 0; i < 9; ++i)
    e += (c.weight[0] * c.vertex[0]->t[i] + c.weight[1] * c.vertex[1]->t[i] +
          c.weight[2] * c.vertex[2]->t[i]) *
         radiance[i];
  return isFinite(e) ? glm::max(e, vec3(0.0f)) : vec3(0.0f);
}

float RelicVisibility::openness(const SurfaceLocation& at) const {
  const Corners c = corners(at);
  return std::clamp(
      c.weight[0] * c.vertex[0]->open + c.weight[1] * c.vertex[1]->open + c.weight[2] * c.vertex[2]->open,
      0.0f, 1.0f);
}

}  // namespace holo::reflect
