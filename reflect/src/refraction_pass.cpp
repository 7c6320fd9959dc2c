#include "refraction_pass.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "clearcoat.hpp"
#include "foreground_walk.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/dfg_table.hpp"
#include "holo/reflect/optics.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {
namespace {

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

}  // namespace

RefractionPass::RefractionPass(const RenderScene& scene, const PrefilteredIbl& ibl,
                               const TracerSettings& settings, int internal_depth, bool refraction,
                               bool clearcoat)
    : scene_(scene),
      ibl_(ibl),
      settings_(settings),
      depth_(std::max(internal_depth, 1)),
      refraction_(refraction),
      clearcoat_(clearcoat),
      supersampling_(scene, ibl, settings, depth_) {}

LayerCounts RefractionPass::shade(const HitPointBuffer& hits, const CameraModel& view,
                                  std::vector<SplitSumShading>& shading, LayerBuffers& buffers) const {
  hits.reservePerSample(buffers.layers);
  hits.reservePerSample(buffers.layered);
  buffers.layers.resize(hits.hits.size());
  buffers.layered.assign(hits.hits.size(), 0);
  // The anchors first (refraction_stride > 1): every sample below reads its neighbours'.
  const AnchorGrid grid = anchorGrid(hits, refraction_ ? settings_.refraction_stride : 1);
  std::atomic<std::uint64_t> rays{traceAnchors(scene_, ibl_, settings_, depth_, hits, grid, buffers.anchors)};
  buffers.anchor_exits = anchorExits(buffers.anchors);
  std::atomic<std::uint64_t> refracted{0}, capped{0}, coated{0}, supersampled{0};
  const std::vector<vec2> pattern = subsamplePattern(4);
  buffers.supersampled.clear();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      LayerCounts local;
                      for (std::size_t k = r.begin(); k < r.end(); ++k)
                        shadePixel(hits, view, grid, pattern, hits.covered[k], shading, buffers, local);
                      rays += local.refraction_rays;
                      refracted += local.refracted_samples;
                      capped += local.capped_paths;
                      coated += local.coated_samples;
                      supersampled += local.supersampled_samples;
                    });
  return {rays.load(), refracted.load(), capped.load(), coated.load(), supersampled.load()};
}

void RefractionPass::shadePixel(const HitPointBuffer& hits, const CameraModel& view, const AnchorGrid& grid,
                                const std::vector<vec2>& pattern, std::size_t p,
                                std::vector<SplitSumShading>& shading, LayerBuffers& buffers,
                                LayerCounts& counts) const {
  TransmittedPath paths[4];
  bool transmits[4] = {false, false, false, false};
  counts.refraction_rays += tracePixelPaths(hits, grid, pattern, p, shading, buffers, paths, transmits);
  const std::size_t first = hits.firstSample(p);
  const int count = hits.sampleCount(p);
  if (count == 4 && supersampling_.sparkles(paths, transmits)) {
    const vec2 centre(float(p % std::size_t(hits.width)), float(p / std::size_t(hits.width)));
    for (int s = 0; s < count; ++s) {
      if (!transmits[s]) continue;
      const std::size_t i = first + std::size_t(s);
      SupersampledPaths more;
      counts.refraction_rays +=
          supersampling_.supersample(view, centre, pattern[std::size_t(s)], paths[s], more);
      paths[s] = meanPath(more);
      buffers.layers[i].source = WalkSource{};
      buffers.layers[i].source.supersampled =
          std::int32_t(buffers.supersampled.push_back(more) - buffers.supersampled.begin());
      ++counts.supersampled_samples;
    }
  }
  writeLayers(hits, p, paths, transmits, shading, buffers, counts);
}

std::uint64_t RefractionPass::tracePixelPaths(const HitPointBuffer& hits, const AnchorGrid& grid,
                                              const std::vector<vec2>& pattern, std::size_t p,
                                              std::vector<SplitSumShading>& shading, LayerBuffers& buffers,
                                              TransmittedPath (&paths)[4], bool (&transmits)[4]) const {
  std::uint64_t rays = 0;
  const vec2 centre(float(p % std::size_t(hits.width)), float(p / std::size_t(hits.width)));
  const std::size_t first = hits.firstSample(p);
  const int count = hits.sampleCount(p);
  // The path of the first sub-sample that traced its own, shared by the pixel's others on
  // the same surface (refraction_stride > 1); shared_source: where its walk comes from.
  RefractionAnchor shared;
  WalkSource shared_source;
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
    const Blend blend = grid.stride > 1 ? blendAnchors(buffers.anchors, grid, 1, hp, at, path, layer.source)
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
        path.environment = iblSeenFrom(ibl_, path.exit_position, path.exit_direction, path.roughness);
    } else {
      // The anchor traced at this very sample has its path already (a refined pixel's anchor
      // sample, which blends its neighbours like any sub-sample and traces where they disagree).
      const RefractionAnchor* own = anchorTracedAt(buffers.anchors, grid, hits, p, i);
      path = own ? own->unit
                 : traceTransmissionPerUnitEntry(scene_, ibl_, settings_, depth_, hp.position, hp.normal,
                                                 -hp.to_viewer, *hp.gltf, &hp.material, nullptr);
      if (grid.stride > 1 && i != p && !shared.material) {
        shared.position = hp.position;
        shared.normal = hp.normal;
        shared.material = hp.gltf;
        shared.unit = path;
        shared_source.shared = std::int32_t(i);
      }
      applyEntry(path);
      if (!own) rays += path.rays;
    }
  }
  return rays;
}

void RefractionPass::writeLayers(const HitPointBuffer& hits, std::size_t p, const TransmittedPath (&paths)[4],
                                 const bool (&transmits)[4], std::vector<SplitSumShading>& shading,
                                 LayerBuffers& buffers, LayerCounts& counts) const {
  const std::size_t first = hits.firstSample(p);
  for (int s = 0; s < hits.sampleCount(p); ++s) {
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
      ++counts.refracted_samples;
      counts.capped_paths += path.exited ? 0 : 1;
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
      const ClearcoatLayer c = shadeClearcoat(ibl_, hp);
      layer.coat_scale = c.scale;
      layer.coat_environment = c.environment;
      sh.specular_scale *= c.below;
      sh.diffuse *= c.below;
      layer.transmit_scale *= c.below;
      ++counts.coated_samples;
    }
    buffers.layered[i] = 1;
  }
}

std::uint64_t RefractionPass::walkTransmitted(const HitPointBuffer& hits, const ForegroundWalk& walk,
                                              LayerBuffers& buffers) const {
  hits.reservePerSample(buffers.transmitted_fg);
  buffers.transmitted_fg.resize(hits.hits.size());
  // The anchors' exit rays first: a blended sample reads the anchors' walks.
  std::atomic<std::uint64_t> walked{
      walkAnchors(buffers.anchors, buffers.anchor_exits, walk, buffers.anchor_fg)};
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
                            local += walkSupersampledPaths(
                                buffers.supersampled[std::size_t(source.supersampled)], walk, fg);
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
