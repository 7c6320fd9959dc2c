#include "glass_transport.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/error.hpp"
#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "inside_glass.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {
namespace {

// An interface's transmitted share of the light past its Fresnel reflection, and the tint it
// transmits with, from its material as the point's textures give it.
float transmittedShare(const SurfaceMaterial& m) {
  return (1.0f - clamp01(m.metallic)) * clamp01(m.transmission);
}

vec3 transmissionTint(const SurfaceMaterial& m) {
  return glm::clamp(m.base_colour, vec3(0.0f), vec3(1.0f));
}

// A material's factors alone, for an entry whose textures were not sampled.
SurfaceMaterial factorsOf(const Material& m) {
  SurfaceMaterial s;
  s.base_colour = m.base_colour;
  s.metallic = m.metallic;
  s.roughness = m.roughness;
  s.specular = m.specular;
  s.specular_colour = m.specular_colour;
  s.transmission = m.transmission;
  s.ior = m.ior;
  s.thin_walled = !(m.thickness > 0.0f);
  s.attenuation_colour = m.attenuation_colour;
  s.attenuation_distance = m.attenuation_distance;
  return s;
}

// Where a transmitted ray meets the relic: every texture slot read there as at a hit point (a
// glass whose metallic-roughness texture makes it clear reads it inside too), the normal on the
// ray's side. Sharpest mip level: the light inside has no pixel footprint of its own.
SurfacePoint meetRelic(const RenderScene& scene, const RayScene& relic, const Ray& ray, const RayHit& hit) {
  return resolveSurface(scene, relic, ray, hit, 0.0f);
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
  return std::clamp(std::sqrt(std::sqrt(alpha2)) * settings.evaluation.transmitted_roughness_scale, 0.0f,
                    1.0f);
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
    const vec3 last_absorption = transmittance(sigma, hit.t);
    weight *= last_absorption;
    const SurfacePoint surface = meetRelic(scene, relic, ray, hit);
    const SurfaceMaterial& m = surface.material;
    position = surface.position;
    vec3 normal = surface.normal;
    if (!isFinite(position) || !isFinite(normal)) break;
    if (!(transmittedShare(m) > 0.0f)) {  // an opaque part inside the glass
      const InsideGlassShading opaque = shadeInsideGlass(scene, ibl, settings, surface, direction);
      path.rays += opaque.rays;
      path.resolved +=
          weight * (opaque.shading.diffuse + opaque.shading.specular_scale * opaque.shading.environment);
      return;
    }
    if (m.thin_walled) break;
    float cos_i = -glm::dot(direction, normal);
    if (!(cos_i > 1e-6f)) {
      normal = surface.geometric_normal;
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
    const float spread = alpha * std::min(safeIor(m.ior) - 1.0f, 2.0f) * 0.5f;
    const vec3 outside = iblSeenFrom(ibl, position, refractIncident(direction, normal, eta),
                                     lobeWidth(settings, alpha2 + spread * spread));
    if (budget > 0 && luminance(weight) * fresnel >= settings.refraction_branch_weight) {
      path.resolved += weight * (1.0f - fresnel) * outside;
      weight *= fresnel;
      direction = reflected_direction;
      alpha2 += alpha * alpha;
      behind = outside;
      has_behind = true;
      continue;
    }
    vec3 back, front;
    parallelWalls(fresnel, last_absorption, back, front);
    path.resolved += weight * back * outside;
    if (has_behind)
      path.resolved += weight * front * behind;
    else
      path.reflected += weight * front;
    return;
  }
  path.resolved += weight * iblSeenFrom(ibl, position, direction, lobeWidth(settings, alpha2));
}

// One transmitted path between its interface events: event() does the event at the point the path
// has reached and gives the ray to cast from there; meet() takes where that ray met the relic and
// says whether the path goes on. The events share the path's running state (throughput, the
// medium, the lobe's width), so they are one object rather than functions passing it around.
class TransmissionWalk {
 public:
  TransmissionWalk(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                   int depth, const vec3& entry_position, const vec3& entry_normal,
                   const vec3& entry_direction, const Material& entry, const SurfaceMaterial* entry_textured,
                   std::vector<glm::dvec3>* alive)
      : scene_(scene),
        ibl_(ibl),
        settings_(settings),
        depth_(depth),
        alive_(alive),
        offset_(std::max(settings.ray_offset, 1e-5f)),
        position_(entry_position),
        normal_(entry_normal),
        geometric_(entry_normal),
        direction_(entry_direction),
        m_(entry_textured ? *entry_textured : factorsOf(entry)),
        branch_budget_(settings.refraction_branch_rays) {}

  // Past `offset` from the interface itself (against meeting it again), so a segment's length is
  // the distance between the interfaces.
  float offset() const { return offset_; }

  // The interface event at (position, normal facing the incoming ray, m); returns the ray on.
  Ray event() {
    float cos_i = -glm::dot(direction_, normal_);
    if (!(cos_i > 1e-6f)) {  // a shading normal turned past the ray: the face's own normal
      normal_ = geometric_;
      cos_i = std::max(-glm::dot(direction_, normal_), 1e-6f);
    }
    const bool first = path_.events == 0;
    const float ior = safeIor(m_.ior);
    const bool thin = m_.thin_walled;
    const float eta = thin || !inside_ ? ior : 1.0f / medium_ior_;
    const float fresnel = fresnelDielectric(cos_i, eta);
    const float transmitted = transmittedShare(m_);
    const vec3 tint = transmissionTint(m_);
    const float alpha = clamp01(m_.roughness) * clamp01(m_.roughness);
    const float spread = alpha * std::min(ior - 1.0f, 2.0f) * 0.5f;
    if (inside_ && !thin && fresnel >= 1.0f) {  // total internal reflection
      direction_ = glm::reflect(direction_, normal_);
      alpha2_ += alpha * alpha;
    } else if (inside_ && !thin) {
      // Leaving: the light that partly reflects inside is followed where it carries a visible
      // share and the budget lasts (a crystal's facets send it out elsewhere), else summed as
      // between parallel walls.
      const vec3 refracted = refractIncident(direction_, normal_, eta);
      vec3 back, front;
      if (branch_budget_ > 0 && luminance(throughput_) * fresnel >= settings_.refraction_branch_weight) {
        const vec3 behind =
            iblSeenFrom(ibl_, position_, refracted, lobeWidth(settings_, alpha2_ + spread * spread));
        followReflected(scene_, ibl_, settings_, position_, glm::reflect(direction_, normal_),
                        throughput_ * fresnel, alpha2_ + alpha * alpha, sigma_, medium_ior_, behind,
                        branch_budget_, path_);
        back = vec3(1.0f - fresnel);
        front = vec3(0.0f);
      } else {
        parallelWalls(fresnel, last_absorption_, back, front);
      }
      alpha2_ += spread * spread;
      path_.reflected += throughput_ * front;
      throughput_ *= back;
      direction_ = refracted;
      inside_ = false;
    } else {
      // Entering (or crossing a thin wall): the entry's reflection and diffuse are the caller's.
      if (!first) {
        path_.reflected += throughput_ * fresnel;
        if (transmitted < 1.0f)
          path_.resolved +=
              throughput_ * (1.0f - fresnel) * (1.0f - transmitted) * tint * ibl_.irradiance(normal_) / kPi;
      }
      const vec3 weight = (1.0f - fresnel) * transmitted * tint;
      if (first)
        path_.entry = weight;
      else
        throughput_ *= weight;
      alpha2_ += spread * spread;
      if (!thin) {
        direction_ = refractIncident(direction_, normal_, eta);
        inside_ = true;
        medium_ior_ = ior;
        sigma_ = attenuationCoefficient(m_.attenuation_colour, m_.attenuation_distance);
      }
    }
    ++path_.events;
    if (alive_ && first) (*alive_)[0] += glm::dvec3(path_.entry * throughput_);
    return Ray{position_, direction_};
  }

  // Where `ray` (the last event()'s) met the relic, cast from offset(); false once the path is
  // done (left the relic, met an opaque part, or reached the cap): path() is then complete.
  bool meet(const Ray& ray, const RayHit& hit) {
    ++path_.rays;
    if (!hit.hit()) {
      leave();
      return false;
    }
    if (inside_) {
      last_absorption_ = transmittance(sigma_, hit.t);
      throughput_ *= last_absorption_;
    }
    const SurfacePoint surface = meetRelic(scene_, scene_.relicOnly(), ray, hit);
    if (!isFinite(surface.position) || !isFinite(surface.normal)) {
      leave();
      return false;
    }
    if (!(transmittedShare(surface.material) > 0.0f)) {
      // An opaque part inside the glass, whatever the depth: shaded where the path meets it, its
      // specular lobe the path's exit (the visitors it reflects are walked along it).
      const InsideGlassShading opaque = shadeInsideGlass(scene_, ibl_, settings_, surface, direction_);
      path_.rays += opaque.rays;
      path_.resolved += throughput_ * opaque.shading.diffuse;
      path_.exited = true;
      path_.exit_position = surface.position + surface.normal * offset_;
      path_.exit_direction = glm::reflect(direction_, surface.normal);
      path_.roughness = clamp01(surface.material.roughness);
      path_.scale = throughput_ * opaque.shading.specular_scale;
      path_.environment = opaque.shading.environment;
      return false;
    }
    if (path_.events >= depth_) {  // the cap: what is left goes to the IBL along the last direction
      path_.resolved += throughput_ * iblSeenFrom(ibl_, position_, direction_, lobe());
      path_.exit_position = position_ + direction_ * offset_;
      path_.exit_direction = direction_;
      path_.roughness = lobe();
      return false;
    }
    position_ = surface.position;
    geometric_ = surface.geometric_normal;
    normal_ = surface.normal;
    m_ = surface.material;
    if (alive_ && path_.events < int(alive_->size()))
      (*alive_)[std::size_t(path_.events)] += glm::dvec3(path_.entry * throughput_);
    return true;
  }

  // The rest of the path, one ray at a time; then path() is complete.
  void finish() {
    const RayScene& relic = scene_.relicOnly();
    for (;;) {
      const Ray ray = event();
      if (!meet(ray, relic.intersect(ray, offset_))) return;
    }
  }

  const TransmittedPath& path() const { return path_; }

 private:
  float lobe() const { return lobeWidth(settings_, alpha2_); }

  // The path left the relic along its last ray.
  void leave() {
    path_.exited = true;
    path_.exit_position = position_ + direction_ * offset_;
    path_.exit_direction = direction_;
    path_.roughness = lobe();
    path_.scale = throughput_;
    path_.environment = iblSeenFrom(ibl_, path_.exit_position, direction_, path_.roughness);
  }

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  const TracerSettings& settings_;
  int depth_;
  std::vector<glm::dvec3>* alive_;
  float offset_;
  TransmittedPath path_;
  vec3 throughput_{1.0f}, last_absorption_{1.0f}, sigma_{0.0f};
  vec3 position_, normal_, geometric_, direction_;
  SurfaceMaterial m_;  // the material of the interface met, as its textures give it there
  bool inside_ = false;
  float medium_ior_ = 1.0f, alpha2_ = 0.0f;
  int branch_budget_;
};

}  // namespace

TransmittedPath traceTransmissionPerUnitEntry(const RenderScene& scene, const PrefilteredIbl& ibl,
                                              const TracerSettings& settings, int depth,
                                              const vec3& entry_position, const vec3& entry_normal,
                                              const vec3& entry_direction, const Material& entry,
                                              const SurfaceMaterial* entry_textured,
                                              std::vector<glm::dvec3>* alive) {
  TransmissionWalk walk(scene, ibl, settings, depth, entry_position, entry_normal, entry_direction, entry,
                        entry_textured, alive);
  walk.finish();
  return walk.path();
}

void traceTransmissionsPerUnitEntry(const RenderScene& scene, const PrefilteredIbl& ibl,
                                    const TracerSettings& settings, int depth,
                                    std::span<const TransmissionEntry> entries,
                                    std::span<TransmittedPath> paths) {
  HOLO_ASSERT(entries.size() == paths.size());
  std::vector<TransmissionWalk> walks;
  std::vector<Ray> rays;
  walks.reserve(entries.size());
  rays.reserve(entries.size());
  for (const TransmissionEntry& e : entries) {
    walks.emplace_back(scene, ibl, settings, depth, e.position, e.normal, e.direction, *e.material,
                       e.textured, nullptr);
    rays.push_back(walks.back().event());
  }
  std::vector<RayHit> hits(rays.size());
  if (!walks.empty())
    scene.relicOnly().intersectPackets(rays, hits, RayCoherence::Coherent, walks.front().offset());
  for (std::size_t k = 0; k < walks.size(); ++k) {
    if (walks[k].meet(rays[k], hits[k])) walks[k].finish();
    paths[k] = walks[k].path();
  }
}

vec3 entryWeight(const vec3& normal, const vec3& direction, const Material& m,
                 const SurfaceMaterial* textured) {
  const float cos_i = std::max(-glm::dot(direction, normal), 1e-6f);
  const float fresnel = fresnelDielectric(cos_i, safeIor(m.ior));
  const SurfaceMaterial surface = textured ? *textured : factorsOf(m);
  return (1.0f - fresnel) * transmittedShare(surface) * transmissionTint(surface);
}

void applyEntry(TransmittedPath& path) {
  path.scale *= path.entry;
  path.resolved *= path.entry;
  path.reflected *= path.entry;
}

TransmittedPath traceTransmission(const RenderScene& scene, const PrefilteredIbl& ibl,
                                  const TracerSettings& settings, int depth, const vec3& entry_position,
                                  const vec3& entry_normal, const vec3& entry_direction,
                                  const Material& entry, const SurfaceMaterial* entry_textured,
                                  std::vector<glm::dvec3>* alive) {
  TransmittedPath path =
      traceTransmissionPerUnitEntry(scene, ibl, settings, depth, entry_position, entry_normal,
                                    entry_direction, entry, entry_textured, alive);
  applyEntry(path);
  return path;
}

}  // namespace holo::reflect
