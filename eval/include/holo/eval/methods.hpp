// The method factory: one view of a ReflectionScene rendered by a named reflection method, timed
// as the evaluations compare them.
//   gt            path-traced ground truth (the true visitors and hall as emitters)
//   ibl           prefiltered static panorama, visitors ignored
//   ibl-baseline  the paper's IBL: the visitors reprojected into the panorama, prefiltered again
//   ours          the voxel-walk reflection tracer (reflect::FrameRenderer)
//   ssrt          screen-space ray tracing of the foreground
//   mcpt          path tracing of the reconstructed foreground (voxels) and the panorama
// Units: milliseconds for times; images are linear HDR CV_32FC3 BGR.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::eval {

inline const std::vector<std::string>& reflectionMethods() {
  static const std::vector<std::string> methods = {"gt", "ibl", "ibl-baseline", "ours", "ssrt", "mcpt"};
  return methods;
}

// What `mcpt` path-traces: the relic, the voxel grid ours walks (built from the scene's
// foreground with `grid`, left empty without visitors) as emitting cubes, and the panorama beyond,
// placed where ours reads it (ReflectionScene::panorama_proxy).
// Constructed in place: the tracer refers to the scene and environment it holds.
struct ReconstructedScene {
  ReconstructedScene(const ReflectionScene& scene, const reflect::VoxelGridSettings& grid, bool with_visitors,
                     std::uint64_t seed);
  ReconstructedScene(const ReconstructedScene&) = delete;
  ReconstructedScene& operator=(const ReconstructedScene&) = delete;

  reflect::RenderScene render_scene;
  reflect::Environment environment;
  reference::PathTracer tracer;
};

struct MethodSettings {
  int spp = 256;                     // gt, mcpt: samples per pixel; ssrt: reflected rays per hit point
  int max_bounces = 5;               // gt: PathTracerOptions::max_bounces
  int max_dielectric_bounces = 256;  // gt: PathTracerOptions::max_dielectric_bounces (glass events)
  int ibl_levels = 10;               // ibl*: roughness levels (PrefilterOptions::levels)
  int ibl_texel_density = 20;        // ibl*: PrefilterOptions::texel_density
  bool with_visitors = true;
  std::uint64_t seed = 1;
  reflect::TracerSettings tracer;  // ours: anti-aliasing, pyramid levels, voxel grid
  // ours: frames rendered after the timed one with nothing moving (the progressive refinement
  // adds a sample set each); the image and the times are the last one's. Default 0: the timed
  // frame follows a moved eye, as in the live loop with the eyes moving.
  int still_frames = 0;
  // ours, ssrt, ibl: the static hall's prefiltered panorama. The hall does not move, so it is
  // built once per scene (staticIbl) and not counted in the per-view time; null = build it here
  // (reported in build_ms; ours, ssrt: outside ms). ibl-baseline always builds its own.
  std::shared_ptr<const reflect::PrefilteredIbl> static_ibl;
};

// The static panorama prefiltered with settings' levels and texel density (what static_ibl holds).
std::shared_ptr<const reflect::PrefilteredIbl> staticIbl(const ReflectionScene& scene,
                                                         const MethodSettings& settings);

struct MethodResult {
  cv::Mat image;        // linear HDR CV_32FC3 BGR
  double ms = 0;        // render time of the view (ibl-baseline, and ibl without static_ibl: the
                        // prefilter build included; ours: the frame's voxel grid and pyramids
                        // included; mcpt: the voxel scene's build included)
  double build_ms = 0;  // IBL, mcpt: part of ms spent building maps or the scene; ours, ssrt:
                        // the static IBL built here when settings.static_ibl was null (not in ms)
  std::vector<std::pair<std::string, double>> passes;  // ours: ms per pass (frame passes first)
  double frame_ms = 0;  // ours: the per-frame passes (voxel grid, pyramids), shared by all views
  double view_ms = 0;   // ours: the per-view passes (hit points, static, walk, composition, tone map)
  std::string plan;     // ours: the last frame's effect plan (EffectPlan::describe)
};

// Throws InputError(field "--method") for an unknown method.
MethodResult renderMethod(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
                          const MethodSettings& settings, bool quiet = true);

}  // namespace holo::eval
