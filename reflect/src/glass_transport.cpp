#include "glass_transport.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "inside_glass.hpp"
#include "layer_inputs.hpp"
#include "relic_passage.hpp"

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

}  // namespace

// One loop over the interface events: each event's branch shares the path's running state
// (throughput, the medium, the lobe's width), which a split would pass around by reference.
TransmittedPath traceTransmissionPerUnitEntry(const RenderScene& scene, const PrefilteredIbl& ibl,
                                              const TracerSettings& settings, int depth,
                                              const vec3& entry_position, const vec3& entry_normal,
                                              const vec3& entry_direction, const Material& entry,
                                              const SurfaceMaterial* entry_textured,
                                              std::vector<glm::dvec3>* alive) {
  TransmittedPath path;
  const RayScene& relic = scene.relicOnly();
  const float offset = std::max(settings.ray_offset, 1e-5f);
  vec3 throughput(1.0f), last_absorption(1.0f), sigma(0.0f);
  vec3 position = entry_position, normal = entry_normal, geometric = entry_normal;
  vec3 direction = entry_direction;
  // The material of the interface met, as its textures give it there.
  SurfaceMaterial m = entry_textured ? *entry_textured : factorsOf(entry);
  bool inside = false;
  float medium_ior = 1.0f, alpha2 = 0.0f;
  int branch_budget = settings.refraction_branch_rays;
  const auto lobe = [&] { return lobeWidth(settings, alpha2); };
  for (;;) {
    // One interface event at (position, normal facing the incoming ray, m).
    float cos_i = -glm::dot(direction, normal);
    if (!(cos_i > 1e-6f)) {  // a shading normal turned past the ray: the face's own normal
      normal = geometric;
      cos_i = std::max(-glm::dot(direction, normal), 1e-6f);
    }
    const bool first = path.events == 0;
    const float ior = safeIor(m.ior);
    const bool thin = m.thin_walled;
    const float eta = thin || !inside ? ior : 1.0f / medium_ior;
    const float fresnel = fresnelDielectric(cos_i, eta);
    const float transmitted = transmittedShare(m);
    const vec3 tint = transmissionTint(m);
    const float alpha = clamp01(m.roughness) * clamp01(m.roughness);
    const float spread = alpha * std::min(ior - 1.0f, 2.0f) * 0.5f;
    if (inside && !thin && fresnel >= 1.0f) {  // total internal reflection
      direction = glm::reflect(direction, normal);
      alpha2 += alpha * alpha;
    } else if (inside && !thin) {
      // Leaving: the light that partly reflects inside is followed where it carries a visible
      // share and the budget lasts (a crystal's facets send it out elsewhere), else summed as
      // between parallel walls.
      const vec3 refracted = refractIncident(direction, normal, eta);
      vec3 back, front;
      if (branch_budget > 0 && luminance(throughput) * fresnel >= settings.refraction_branch_weight) {
        const vec3 behind =
            iblSeenFrom(ibl, position, refracted, lobeWidth(settings, alpha2 + spread * spread));
        followReflected(scene, ibl, settings, position, glm::reflect(direction, normal), throughput * fresnel,
                        alpha2 + alpha * alpha, sigma, medium_ior, behind, branch_budget, path);
        back = vec3(1.0f - fresnel);
        front = vec3(0.0f);
      } else {
        parallelWalls(fresnel, last_absorption, back, front);
      }
      alpha2 += spread * spread;
      path.reflected += throughput * front;
      throughput *= back;
      direction = refracted;
      inside = false;
    } else {
      // Entering (or crossing a thin wall): the entry's reflection and diffuse are the caller's.
      if (!first) {
        // Reflected along its own mirror direction: a bowl's back wall, seen through the front
        // one, sends it where the entry's mirror does not (its concave inside faces the sky). On
        // its way back through the walls it loses no Fresnel share: they reflect about as much
        // light into it as out of it (relic_passage.hpp).
        const vec3 mirror = glm::reflect(direction, normal);
        path.resolved +=
            throughput * fresnel *
            passedThroughRelic(scene, settings, position, mirror, path.rays, InterfaceLoss::None) *
            iblSeenFrom(ibl, position, mirror, lobe());
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
        direction = refractIncident(direction, normal, eta);
        inside = true;
        medium_ior = ior;
        sigma = attenuationCoefficient(m.attenuation_colour, m.attenuation_distance);
      }
    }
    ++path.events;
    if (alive && first) (*alive)[0] += glm::dvec3(path.entry * throughput);
    // From the interface itself, past `offset` (against meeting it again), so a segment's length
    // is the distance between the interfaces.
    const Ray ray{position, direction};
    const RayHit hit = relic.intersect(ray, offset);
    ++path.rays;
    if (!hit.hit()) break;
    if (inside) {
      last_absorption = transmittance(sigma, hit.t);
      throughput *= last_absorption;
    }
    const SurfacePoint surface = meetRelic(scene, relic, ray, hit);
    if (!isFinite(surface.position) || !isFinite(surface.normal)) break;
    if (!(transmittedShare(surface.material) > 0.0f)) {
      // An opaque part inside the glass, whatever the depth: shaded where the path meets it, its
      // specular lobe the path's exit (the visitors it reflects are walked along it).
      const InsideGlassShading opaque = shadeInsideGlass(scene, ibl, settings, surface, direction);
      path.rays += opaque.rays;
      path.resolved += throughput * opaque.shading.diffuse;
      path.exited = true;
      path.exit_position = surface.position + surface.normal * offset;
      path.exit_direction = glm::reflect(direction, surface.normal);
      path.roughness = clamp01(surface.material.roughness);
      path.scale = throughput * opaque.shading.specular_scale;
      path.environment = opaque.shading.environment;
      return path;
    }
    if (path.events >= depth) {  // the cap: what is left goes to the IBL along the last direction
      path.resolved += throughput * iblSeenFrom(ibl, position, direction, lobe());
      path.exit_position = position + direction * offset;
      path.exit_direction = direction;
      path.roughness = lobe();
      return path;
    }
    position = surface.position;
    geometric = surface.geometric_normal;
    normal = surface.normal;
    m = surface.material;
    if (alive && path.events < int(alive->size()))
      (*alive)[std::size_t(path.events)] += glm::dvec3(path.entry * throughput);
  }
  path.exited = true;
  path.exit_position = position + direction * offset;
  path.exit_direction = direction;
  path.roughness = lobe();
  path.scale = throughput;
  path.environment = iblSeenFrom(ibl, path.exit_position, direction, path.roughness);
  return path;
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

vec3 lightThroughGlass(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                       const SurfacePoint& surface, const vec3& direction, std::uint64_t& rays) {
  const int depth = settings.refraction_depth > 0 ? settings.refraction_depth : kMaxInternalDepth;
  const TransmittedPath path = traceTransmission(scene, ibl, settings, depth, surface.position,
                                                 surface.normal, direction, Material{}, &surface.material);
  rays += path.rays;
  vec3 light = path.resolved + path.scale * path.environment;
  if (luminance(path.reflected) > 0.0f)
    light += path.reflected * iblSeenFrom(ibl, surface.position, glm::reflect(direction, surface.normal),
                                          clamp01(surface.material.roughness));
  return isFinite(light) ? light : vec3(0.0f);
}

}  // namespace holo::reflect
