// The frame renderer's refraction pass (internal): the material layers on top of the static
// shading of each hit point, refraction through transmissive relic materials
// (KHR_materials_transmission, _volume, _ior) and the clearcoat's second specular lobe
// (KHR_materials_clearcoat). Each mechanism has its own file; this pass runs them per sample:
//  * glass transport (glass_transport.hpp): at a transmissive hit point the reflection is rescaled
//    to the exact Fresnel of its IOR, the diffuse by 1 - transmission, and the transmitted light is
//    traced through the relic, up to EffectPlan::internal_depth interface events (measured by the
//    internal-depth probe, internal_depth.hpp, where TracerSettings::refraction_depth is 0);
//  * sparse anchors (refraction_anchors.hpp, TracerSettings::refraction_stride > 1): paths traced
//    on a lattice of anchors, blended between agreeing anchors elsewhere; a refined pixel's
//    sub-samples on the same surface share one path;
//  * supersampling (refraction_supersampling.hpp): a four-sample pixel whose transmitted light
//    sparkles takes 16 paths across each sample's quarter;
//  * the clearcoat (clearcoat.hpp), over the base's reflection, diffuse and transmitted light.
// The visitors seen through the glass are walked along the paths' exit rays every frame
// (walkTransmitted), the anchors' walks blended where these see the same.
#pragma once

#include <cstdint>
#include <vector>

#include <tbb/concurrent_vector.h>

#include "glass_transport.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tracer_settings.hpp"
#include "refraction_anchors.hpp"
#include "refraction_supersampling.hpp"

namespace holo::reflect {

class ForegroundWalk;

// Per sample of a view's hit points: the transmitted path and the coat.
struct SampleLayers {
  vec3 transmit_scale{0.0f}, transmit_environment{0.0f};
  vec3 exit_position{0.0f}, exit_direction{0.0f, 0.0f, 1.0f};
  float exit_roughness = 0.0f;
  bool walks = false;  // the exit ray's visitors are read (walked, or blended per `source`)
  WalkSource source;
  vec3 coat_scale{0.0f}, coat_environment{0.0f};
};

struct LayerBuffers {
  std::vector<SampleLayers> layers;  // per entry of hits.hits; meaningful where layered[i]
  std::vector<std::uint8_t> layered;
  std::vector<ForegroundSample> transmitted_fg;  // per entry, this frame's visitors along the exit rays
  std::vector<RefractionAnchor> anchors;         // the anchor grid, row-major (kept with the static shading)
  AnchorExits anchor_exits;                      // the anchors whose exit rays are walked
  std::vector<ForegroundSample> anchor_fg;       // per anchor, this frame's walk of its exit ray
  tbb::concurrent_vector<SupersampledPaths> supersampled;  // in no fixed order
};

struct LayerCounts {
  std::uint64_t refraction_rays = 0;    // Embree rays of the transmitted paths
  std::uint64_t refracted_samples = 0;  // samples with a transmitted path (traced or blended)
  std::uint64_t capped_paths = 0;       // paths that reached the depth cap
  std::uint64_t coated_samples = 0;
  std::uint64_t supersampled_samples = 0;  // samples whose transmitted light is a mean of paths
};

class RefractionPass {
 public:
  // Everything must outlive this. refraction / clearcoat: whether the plan runs them.
  RefractionPass(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                 int internal_depth, bool refraction, bool clearcoat);

  // Every valid sample of a covered pixel with a transmissive or coated material: its shading
  // rescaled (the reflection by the exact Fresnel, the diffuse by 1 - transmission, the base by
  // the coat), its layers written. shading as StaticShading wrote it; `view`: the camera the hit
  // points were traced from (the supersampled paths' primary rays).
  LayerCounts shade(const HitPointBuffer& hits, const CameraModel& view,
                    std::vector<SplitSumShading>& shading, LayerBuffers& buffers) const;
  // This frame's visitors along the exit rays into buffers.transmitted_fg: the anchors' exit rays
  // and those of the samples that traced their own path are walked, a blended sample takes the
  // blend of its anchors' walks where these see the same (the transmitted lobe is blurred like its
  // path) and walks its own elsewhere. Returns the rays walked.
  std::uint64_t walkTransmitted(const HitPointBuffer& hits, const ForegroundWalk& walk,
                                LayerBuffers& buffers) const;

 private:
  // shade() for covered pixel p, adding to `counts`.
  void shadePixel(const HitPointBuffer& hits, const CameraModel& view, const AnchorGrid& grid,
                  const std::vector<vec2>& pattern, std::size_t p, std::vector<SplitSumShading>& shading,
                  LayerBuffers& buffers, LayerCounts& counts) const;
  // The transmitted path of each of pixel p's transmissive samples (transmits[s]), traced, blended
  // from the anchors or shared with a sub-sample on the same surface, entry weights applied; their
  // reflection rescaled. Returns the Embree rays cast.
  std::uint64_t tracePixelPaths(const HitPointBuffer& hits, const AnchorGrid& grid,
                                const std::vector<vec2>& pattern, std::size_t p,
                                std::vector<SplitSumShading>& shading, LayerBuffers& buffers,
                                TransmittedPath (&paths)[4], bool (&transmits)[4]) const;
  // Writes the layers of pixel p's samples: their transmitted paths and their coats.
  void writeLayers(const HitPointBuffer& hits, std::size_t p, const TransmittedPath (&paths)[4],
                   const bool (&transmits)[4], std::vector<SplitSumShading>& shading, LayerBuffers& buffers,
                   LayerCounts& counts) const;

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  const TracerSettings& settings_;
  int depth_;
  bool refraction_, clearcoat_;
  RefractionSupersampling supersampling_;
};

}  // namespace holo::reflect
