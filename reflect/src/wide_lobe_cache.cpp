#include "wide_lobe_cache.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "holo/core/error.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/effect_plan.hpp"

namespace holo::reflect {
namespace {

// The hemi-octahedral square [-1, 1]^2 of a local direction with z >= 0 (continuous over the
// hemisphere, the horizon on the square's edges).
vec2 hemiOctahedral(const vec3& d) {
  const float sum = std::abs(d.x) + std::abs(d.y) + std::max(d.z, 0.0f);
  const float px = d.x / sum, py = d.y / sum;
  return {px + py, px - py};
}

}  // namespace

WideLobeCache::WideLobeCache(const RenderScene& scene, int bins) : relic_(scene.relic()), bins_(bins) {
  if (bins < 2 || bins > 16)
    throw InputError("tracer settings", "wide_lobe_cache_bins", "2..16", std::to_string(bins));
  const auto wide = [](float roughness) { return roughness >= kGlossyRoughnessLimit; };
  const std::size_t meshes = relic_.meshes.size();
  covered_.assign(meshes, 0);
  frames_.resize(meshes);
  entries_.resize(meshes);
  for (std::size_t m = 0; m < meshes; ++m) {
    const TriangleMesh& mesh = relic_.meshes[m];
    if (mesh.triangles.empty()) continue;
    const int index = mesh.material;
    const Material* material = index >= 0 && std::size_t(index) < relic_.materials.size()
                                   ? &relic_.materials[std::size_t(index)]
                                   : nullptr;
    bool covered = false;
    if (const auto& override_material = scene.relicMaterialOverride())
      covered = wide(override_material->roughness);
    else if (material)
      covered = wide(material->roughness) && !material->metallic_roughness_texture.used();
    if (!covered) continue;
    covered_[m] = 1;
    active_ = true;
    std::vector<vec3> normals = mesh.normals;
    if (normals.size() != mesh.positions.size()) {
      TriangleMesh copy = mesh;
      copy.computeNormals();
      normals = copy.normals;
    }
    const std::size_t count = mesh.positions.size() * std::size_t(bins_ * bins_);
    const bool two_sided = material && (material->double_sided || material->transmission > 0.0f);
    for (int side = 0; side < (two_sided ? 2 : 1); ++side) {
      entries_[m][std::size_t(side)] = std::make_unique<Entry[]>(count);
      for (const vec3& normal : normals) {
        const float len = glm::length(normal);
        if (len > 1e-12f && std::isfinite(len))
          frames_[m][std::size_t(side)].emplace_back(Frame((side == 0 ? 1.0f : -1.0f) * normal / len));
        else
          frames_[m][std::size_t(side)].emplace_back(std::nullopt);
      }
    }
  }
}

WideLobeCache::~WideLobeCache() = default;

bool WideLobeCache::covers(const SurfaceLocation& at) const {
  return at.located() && at.mesh < covered_.size() && covered_[at.mesh] &&
         entries_[at.mesh][at.front ? 0 : 1];
}

void WideLobeCache::clear() {
  for (std::size_t m = 0; m < entries_.size(); ++m)
    for (int side = 0; side < 2; ++side) {
      Entry* entries = entries_[m][std::size_t(side)].get();
      if (!entries) continue;
      const std::size_t count = relic_.meshes[m].positions.size() * std::size_t(bins_ * bins_);
      for (std::size_t k = 0; k < count; ++k) entries[k].state.store(0, std::memory_order_relaxed);
    }
}

vec3 WideLobeCache::binDirection(int i, int j) const {
  const float u = (float(i) + 0.5f) / float(bins_) * 2.0f - 1.0f,
              v = (float(j) + 0.5f) / float(bins_) * 2.0f - 1.0f;
  const float px = 0.5f * (u + v), py = 0.5f * (u - v);
  return glm::normalize(vec3(px, py, std::max(1.0f - std::abs(px) - std::abs(py), 0.0f) + 1e-3f));
}

const LobeBounce& WideLobeCache::entry(std::size_t mesh, int side, std::uint32_t vertex, int bin,
                                       const Frame& frame, const Trace& trace, LobeBounce& scratch) const {
  Entry& e =
      entries_[mesh][std::size_t(side)][std::size_t(vertex) * std::size_t(bins_ * bins_) + std::size_t(bin)];
  if (e.state.load(std::memory_order_acquire) == 2) return e.value;
  const LobeBounce value = trace(relic_.meshes[mesh].positions[vertex], frame.n,
                                 frame.toWorld(binDirection(bin % bins_, bin / bins_)));
  std::uint8_t empty = 0;
  if (e.state.compare_exchange_strong(empty, 1, std::memory_order_acq_rel)) {
    e.value = value;
    e.state.store(2, std::memory_order_release);
    computed_.fetch_add(1, std::memory_order_relaxed);
  }
  // Another thread computing the same entry stores the same value; this one's copy serves now.
  scratch = value;
  return scratch;
}

LobeBounce WideLobeCache::lookup(const SurfaceLocation& at, const vec3& to_viewer, const Trace& trace) const {
  const int side = at.front ? 0 : 1;
  const TriangleMesh& mesh = relic_.meshes[at.mesh];
  const auto& frames = frames_[at.mesh][std::size_t(side)];
  const uvec3 tri = mesh.triangles[at.triangle];
  const float bary[3] = {1.0f - at.barycentric.x - at.barycentric.y, at.barycentric.x, at.barycentric.y};
  const std::uint32_t corners[3] = {tri.x, tri.y, tri.z};
  LobeBounce sum, scratch;
  for (int c = 0; c < 3; ++c) {
    if (!(bary[c] > 0.0f)) continue;
    const std::uint32_t vertex = corners[c];
    if (!frames[vertex]) continue;
    const Frame& frame = *frames[vertex];
    vec3 wo = frame.toLocal(to_viewer);
    wo.z = std::max(wo.z, 0.0f);
    if (!(glm::length(wo) > 0.0f)) continue;
    const vec2 square = hemiOctahedral(glm::normalize(wo));
    // Bilinear over the bin centres (clamped at the square's edges).
    const vec2 g =
        glm::clamp((square + 1.0f) * 0.5f * float(bins_) - 0.5f, vec2(0.0f), vec2(float(bins_ - 1)));
    const int i0 = std::min(int(g.x), bins_ - 2), j0 = std::min(int(g.y), bins_ - 2);
    const float fx = g.x - float(i0), fy = g.y - float(j0);
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const float w = bary[c] * (di ? fx : 1.0f - fx) * (dj ? fy : 1.0f - fy);
        if (!(w > 0.0f)) continue;
        const int bin = (j0 + dj) * bins_ + (i0 + di);
        sum.add(entry(at.mesh, side, vertex, bin, frame, trace, scratch), w);
      }
  }
  return sum;
}

}  // namespace holo::reflect
