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
                      BlockPaths block;
                      block.pixels.resize(r.size());
                      for (std::size_t k = r.begin(); k < r.end(); ++k)
                        choosePaths(hits, grid, pattern, hits.covered[k], shading, buffers,
                                    block.pixels[k - r.begin()], block);
                      // The samples that trace their own path, together: neighbours at a
                      // silhouette or crease start their first segments alike.
                      block.traced.resize(block.entries.size());
                      traceTransmissionsPerUnitEntry(scene_, ibl_, settings_, depth_, block.entries,
                                                     block.traced);
                      for (std::size_t k = r.begin(); k < r.end(); ++k)
                        finishPixel(hits, view, pattern, hits.covered[k], block.pixels[k - r.begin()], block,
                                    shading, buffers, local);
                      rays += local.refraction_rays;
                      refracted += local.refracted_samples;
                      capped += local.capped_paths;
                      coated += local.coated_samples;
                      supersampled += local.supersampled_samples;
                    });
  return {rays.load(), refracted.load(), capped.load(), coated.load(), supersampled.load()};
}

void RefractionPass::choosePaths(const HitPointBuffer& hits, const AnchorGrid& grid,
                                 const std::vector<vec2>& pattern, std::size_t p,
                                 std::vector<SplitSumShading>& shading, LayerBuffers& buffers,
                                 PixelPaths& pixel, BlockPaths& block) const {
  const vec2 centre(float(p % std::size_t(hits.width)), float(p / std::size_t(hits.width)));
  const std::size_t first = hits.firstSample(p);
  const int count = hits.sampleCount(p);
  // The first sub-sample that traces its own path shares it with the pixel's others on the same
  // surface (refraction_stride > 1): its hit point, and where its path will be in block.traced.
  const HitPoint* owner = nullptr;
  std::int32_t owner_entry = -1;
  WalkSource owner_source;
  for (int s = 0; s < count; ++s) {
    const std::size_t i = first + std::size_t(s);
    if (!hits.valid[i] || hits.hits[i].gltf == nullptr) continue;
    const HitPoint& hp = hits.hits[i];
    if (!(refraction_ && hp.gltf->transmission > 0.0f)) continue;
    pixel.transmits[s] = true;
    buffers.layers[i] = SampleLayers{};
    SampleLayers& layer = buffers.layers[i];
    rescaleReflection(hp, shading[i]);
    const vec2 at = centre + (i == p ? vec2(0.0f) : pattern[std::size_t(s)]);
    const Blend blend = grid.stride > 1
                            ? blendAnchors(buffers.anchors, grid, 1, hp, at, pixel.paths[s], layer.source)
                            : Blend::EventsDiffer;
    // Where the anchors meet other events inside, the path changes within the pixel: each
    // sub-sample traces its own there rather than share one.
    if (blend == Blend::Blended) {
      pixel.entry[s] = PixelPaths::kBlended;
      continue;
    }
    if (blend == Blend::NotBlended && owner &&
        sameSurface(RefractionAnchor{owner->position, owner->normal, owner->gltf, {}, {}}, hp)) {
      pixel.entry[s] = PixelPaths::kShared - owner_entry;
      layer.source = owner_source;
      continue;
    }
    pixel.entry[s] = std::int32_t(block.entries.size());
    if (grid.stride > 1 && i != p && !owner) {
      owner = &hp;
      owner_entry = pixel.entry[s];
      owner_source = WalkSource{};
      owner_source.shared = std::int32_t(i);
    }
    block.entries.push_back({hp.position, hp.normal, -hp.to_viewer, hp.gltf, &hp.material});
  }
}

void RefractionPass::finishPixel(const HitPointBuffer& hits, const CameraModel& view,
                                 const std::vector<vec2>& pattern, std::size_t p, PixelPaths& pixel,
                                 const BlockPaths& block, std::vector<SplitSumShading>& shading,
                                 LayerBuffers& buffers, LayerCounts& counts) const {
  const std::size_t first = hits.firstSample(p);
  const int count = hits.sampleCount(p);
  for (int s = 0; s < count; ++s) {
    if (!pixel.transmits[s]) continue;
    const HitPoint& hp = hits.hits[first + std::size_t(s)];
    TransmittedPath& path = pixel.paths[s];
    const std::int32_t entry = pixel.entry[s];
    if (entry >= 0) {  // traced its own
      path = block.traced[std::size_t(entry)];
      applyEntry(path);
      counts.refraction_rays += path.rays;
      continue;
    }
    if (entry != PixelPaths::kBlended) path = block.traced[std::size_t(PixelPaths::kShared - entry)];
    path.entry = entryWeight(hp.normal, -hp.to_viewer, *hp.gltf, &hp.material);
    applyEntry(path);
    if (path.exited)
      path.environment = iblSeenFrom(ibl_, path.exit_position, path.exit_direction, path.roughness);
  }
  if (count == 4 && supersampling_.sparkles(pixel.paths, pixel.transmits)) {
    const vec2 centre(float(p % std::size_t(hits.width)), float(p / std::size_t(hits.width)));
    for (int s = 0; s < count; ++s) {
      if (!pixel.transmits[s]) continue;
      const std::size_t i = first + std::size_t(s);
      SupersampledPaths more;
      counts.refraction_rays +=
          supersampling_.supersample(view, centre, pattern[std::size_t(s)], pixel.paths[s], more);
      pixel.paths[s] = meanPath(more);
      buffers.layers[i].source = WalkSource{};
      buffers.layers[i].source.supersampled =
          std::int32_t(buffers.supersampled.push_back(more) - buffers.supersampled.begin());
      ++counts.supersampled_samples;
    }
  }
  writeLayers(hits, p, pixel.paths, pixel.transmits, shading, buffers, counts);
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
