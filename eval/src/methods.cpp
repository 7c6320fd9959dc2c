#include "holo/eval/methods.hpp"

#include <algorithm>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/reference/foreground_environment.hpp"
#include "holo/reference/ibl_renderer.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reference/ssrt.hpp"
#include "holo/reference/voxel_emitters.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::eval {

std::shared_ptr<const reflect::PrefilteredIbl> staticIbl(const ReflectionScene& scene,
                                                         const MethodSettings& settings) {
  const reflect::Environment env(scene.panorama, 0.0f, scene.panorama_proxy);
  reflect::PrefilterOptions po;
  po.levels = settings.ibl_levels;
  po.texel_density = settings.ibl_texel_density;
  return std::make_shared<const reflect::PrefilteredIbl>(env, po);
}

namespace {

std::vector<Model> voxelEmittersOf(const ReflectionScene& scene, const reflect::VoxelGridSettings& settings,
                                   bool with_visitors) {
  reflect::VoxelGrid grid(settings);
  if (with_visitors) grid.build(scene.foreground);
  std::vector<Model> emitters;
  if (!grid.empty()) emitters.push_back(reference::voxelEmitters(grid));
  return emitters;
}

reference::PathTracerOptions seeded(std::uint64_t seed) {
  reference::PathTracerOptions options;
  options.seed = seed;
  return options;
}

}  // namespace

ReconstructedScene::ReconstructedScene(const ReflectionScene& scene, const reflect::VoxelGridSettings& grid,
                                       bool with_visitors, std::uint64_t seed)
    : render_scene(scene.relic, voxelEmittersOf(scene, grid, with_visitors)),
      environment(scene.panorama, 0.0f, scene.panorama_proxy),
      tracer(render_scene, environment, seeded(seed)) {}

MethodResult renderMethod(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
                          const MethodSettings& settings, bool quiet) {
  MethodResult r;
  const Stopwatch total;
  if (method == "gt") {
    std::vector<Model> emitters = scene.static_emitters;
    if (settings.with_visitors && !scene.visitors.meshes.empty()) emitters.push_back(scene.visitors);
    Model relic = scene.relic;
    if (scene.plinth) appendPlinth(relic, placePlinth(*scene.plinth, scene.relic.bounds()));
    const reflect::RenderScene rs(relic, emitters);
    const reflect::Environment env(scene.panorama);
    reference::PathTracerOptions options;
    options.seed = settings.seed;
    options.max_bounces = settings.max_bounces;
    options.max_dielectric_bounces = settings.max_dielectric_bounces;
    const reference::PathTracer tracer(rs, env, options);
    reference::PathTracerStats stats;
    r.image = reference::renderPathTraced(tracer, camera, std::max(1, settings.spp), &stats, quiet);
    // Debug: every opaque relic's gt has paths its 5-bounce cap stopped; evaluations render many.
    if (stats.truncated > 0)
      HOLO_LOG_DEBUG(
          "gt: {} of {} path samples stopped by a bounce cap; their throughput, {:.3g} per sample, is what "
          "they would still carry from an environment of 1 (the image's mean luminance per sample is {:.3g})",
          stats.truncated, stats.samples, stats.truncated_throughput / double(stats.samples),
          stats.total_energy / double(stats.samples));
  } else if (method == "ibl" && settings.static_ibl) {
    // The static map is built once per scene: the per-view cost is the shading alone (the
    // relic's Embree scene is built once too, as for ours).
    const reflect::RenderScene rs(scene.relic, {});
    const Stopwatch view;
    r.image = reference::renderIbl(rs, *settings.static_ibl, camera);
    r.ms = view.ms();
    return r;
  } else if (method == "ibl" || method == "ibl-baseline") {
    const reflect::RenderScene rs(scene.relic, {});
    const bool merge = method == "ibl-baseline" && settings.with_visitors;
    const Bounds3 b = scene.relic.bounds();
    const cv::Mat pano = merge ? reference::mergeForeground(scene.panorama, scene.foreground,
                                                            b.empty() ? vec3(0.0f) : b.center())
                               : scene.panorama;
    const reflect::Environment env(pano);
    reflect::PrefilterOptions po;
    po.levels = settings.ibl_levels;
    po.texel_density = settings.ibl_texel_density;
    const reflect::PrefilteredIbl ibl(env, po);
    r.build_ms = total.ms();
    r.image = reference::renderIbl(rs, ibl, camera);
  } else if (method == "ours" || method == "ssrt") {
    const reflect::RenderScene rs(scene.relic, {});
    std::shared_ptr<const reflect::PrefilteredIbl> ibl = settings.static_ibl;
    if (!ibl) {
      ibl = staticIbl(scene, settings);
      r.build_ms = total.ms();
    }
    static const depthfilter::ForegroundCloud kNobody;
    const depthfilter::ForegroundCloud& cloud = settings.with_visitors ? scene.foreground : kNobody;
    if (method == "ours") {
      reflect::TracerSettings tracer = settings.tracer;
      if (scene.plinth) tracer.plinth = scene.plinth;
      reflect::FrameRenderer renderer(rs, *ibl, tracer);
      // Timed as the live loop runs it, where the eyes move every frame: buffers already
      // allocated and touched by a frame before (the grid, the pyramids, the view's hit points),
      // the view's static passes traced again (the eye 1 mm away: no reuse).
      CameraModel moved_eye = camera;
      mat4 pose = camera.T_world_camera();
      pose[3] += vec4(0.001f, 0.0f, 0.0f, 0.0f);
      moved_eye.setPose(pose);
      renderer.render(cloud, scene.foreground_cameras, {moved_eye});
      const Stopwatch view;
      reflect::FrameResult fr = renderer.render(cloud, scene.foreground_cameras, {camera});
      r.ms = view.ms();
      for (int i = 0; i < settings.still_frames; ++i) {
        const Stopwatch still;
        fr = renderer.render(cloud, scene.foreground_cameras, {camera});
        r.ms = still.ms();
      }
      for (const reflect::PassTiming& p : fr.frame_timings) {
        r.passes.emplace_back(reflect::passName(p.pass), p.ms);
        r.frame_ms += p.ms;
      }
      for (const reflect::PassTiming& p : fr.views.at(0).timings) {
        r.passes.emplace_back(reflect::passName(p.pass), p.ms);
        r.view_ms += p.ms;
      }
      r.image = std::move(fr.views.at(0).hdr);
      r.plan = fr.plan.describe();
    } else {
      reference::SsrtSettings ss;
      ss.rays = std::max(1, settings.spp);
      ss.seed = settings.seed;
      const Stopwatch view;
      r.image = reference::renderSsrt(rs, *ibl, cloud, camera, ss);
      r.ms = view.ms();
    }
    return r;
  } else if (method == "mcpt") {
    const ReconstructedScene reconstruction(scene, reflect::VoxelGridSettings{}, settings.with_visitors,
                                            settings.seed);
    r.build_ms = total.ms();
    r.image =
        reference::renderPathTraced(reconstruction.tracer, camera, std::max(1, settings.spp), nullptr, quiet);
  } else {
    std::string names;
    for (const auto& m : reflectionMethods()) names += (names.empty() ? "" : ", ") + m;
    throw InputError("command line", "--method", "one of " + names, method);
  }
  r.ms = total.ms();
  return r;
}

}  // namespace holo::eval
