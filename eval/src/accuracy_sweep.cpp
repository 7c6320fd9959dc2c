#include "holo/eval/accuracy_sweep.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/eval/ground_truth_cache.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/eval/scoring.hpp"
#include "holo/reference/image_metrics.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reference/voxel_emitters.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::eval {
namespace {

constexpr int kViewsPerFrame = 4;  // the per-frame work is shared by the four face views

std::string fmt(double v, int precision) {
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

// Marks the points no other point beats on both time and fg_mse.
void markPareto(std::vector<AccuracyPoint>& points) {
  for (AccuracyPoint& p : points) {
    p.pareto = true;
    for (const AccuracyPoint& q : points)
      if (&q != &p && q.ms <= p.ms && q.fg_mse <= p.fg_mse && (q.ms < p.ms || q.fg_mse < p.fg_mse)) {
        p.pareto = false;
        break;
      }
  }
}

const AccuracyPoint* effectPoint(const AccuracySweep& sweep, const std::string& effect) {
  for (const AccuracyPoint& p : sweep.points)
    if (p.method == "ours" && p.effect == effect) return &p;
  return nullptr;
}

std::string sceneName(const AccuracyOptions& o) {
  return o.hall + " x " + o.relic;
}

}  // namespace

std::vector<std::string> effectVariants() {
  return {"default",          "SelfOcclusion off",     "RoughLobe off",
          "VisitorLight off", "AxisAlignedFilter off", "ProgressiveRefinement on"};
}

std::vector<std::string> effectScenes() {
  std::vector<std::string> scenes;
  for (const char* hall : {"room", "gallery", "atrium"})
    for (const char* relic : {"vase", "kettle", "tripod"}) scenes.push_back(std::string(hall) + ":" + relic);
  for (const char* scene : {"gallery:bowl", "gallery:metal-bowl", "window:bowl"}) scenes.emplace_back(scene);
  return scenes;
}

AccuracySweep sweepAccuracy(const AccuracyOptions& o) {
  AccuracySweep sweep;
  const VisitorScene setup = visitorScene(o.hall, o.relic, o.close_visitors, o.camera_tilt_deg,
                                          o.camera_vfov_deg, o.size, o.visitor_model, o.panorama_at_infinity);
  const ReflectionScene& scene = setup.scene;
  const CameraModel& camera = setup.camera;
  const VisitorView& pick = setup.pick;
  sweep.frame = pick.frame;
  sweep.face = pick.face;
  HOLO_LOG_INFO("bench accuracy: {} x {}, frame {}, face {}", o.hall, o.relic, pick.frame, pick.face);

  const cv::Mat gt_hdr = cachedGroundTruth(scene, camera, o.gt_spp, true, o.cache);
  const ForegroundScoring scoring = foregroundScoring(
      gt_hdr, cachedGroundTruth(scene, camera, o.gt_spp, false, o.cache), reference::kForegroundDistance);
  sweep.region_pixels = scoring.region_pixels;
  const auto score = [&](AccuracyPoint& p, const cv::Mat& hdr) {
    p.mse = scoring.mse(hdr);
    p.fg_mse = scoring.foregroundMse(hdr);
  };

  MethodSettings base;
  base.static_ibl = staticIbl(scene, base);
  std::vector<AccuracyPoint>& points = sweep.points;
  // One configuration: the median time of `repeats` runs (per view, frame work / 4), the first image.
  const auto run = [&](const std::string& method, const std::string& knob, const MethodSettings& s,
                       const std::string& effect) {
    AccuracyPoint p{method, knob, effect, "", 0, 0, 0, false};
    std::vector<double> ms;
    cv::Mat image;
    for (int i = 0; i < o.repeats; ++i) {
      const MethodResult r = renderMethod(method == "ibl" ? "ibl-baseline" : method, scene, camera, s);
      ms.push_back(method == "ours" ? r.view_ms + r.frame_ms / kViewsPerFrame
                                    : (r.ms - r.build_ms) + r.build_ms / kViewsPerFrame);
      if (i == 0) {
        image = r.image;
        p.plan = r.plan;
      }
    }
    p.ms = median(ms);
    score(p, image);
    points.push_back(p);
  };

  struct OursConfig {
    int aa, levels;
    float voxel, bias;
    int lobe_components;
    int refraction_depth = 0;  // 0: measured on the relic
    float transmitted_roughness_scale = 1.0f;
    int refraction_stride = reflect::TracerSettings{}.refraction_stride;
    int refraction_branch_rays = reflect::TracerSettings{}.refraction_branch_rays;
    float refraction_supersample_contrast = reflect::TracerSettings{}.refraction_supersample_contrast;
    // The effect plan's entries, each switched against the default tracer (kEffectVariants).
    std::string effect = "";     // "" for a quality knob's point
    bool self_occlusion = true;  // false: the unoccluded irradiance
    bool rough_lobe = true;      // false: the mirror ray at every roughness
    bool visitor_light = true;   // false: the diffuse lit by the empty hall
    bool lobe_filter = true;     // false: the rough lobe's interreflection unfiltered
    int lobe_grid = reflect::TracerSettings{}.rough_interreflection_grid;  // its strata, a side
    int still_frames = 0;  // > 0: the progressive refinement's frames with nothing moving
  };
  const int lobe = reflect::TracerSettings{}.lobe_components;
  const reflect::TracerSettings d;
  const OursConfig default_tracer{d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe};
  std::vector<OursConfig> ours;
  if (!o.effects_only) {
    for (int aa : {1, 4})
      for (int levels : {5, 7, 9})
        for (float voxel : {0.02f, 0.03125f, 0.05f}) ours.push_back({aa, levels, voxel, 0.0f, lobe});
    for (float bias : {-1.0f, 1.0f}) ours.push_back({4, 9, 0.03125f, bias, lobe});
    for (int components : {1, 4}) ours.push_back({4, 9, 0.03125f, 0.0f, components});
  }
  for (const std::string& effect : effectVariants()) {
    OursConfig c = default_tracer;
    c.effect = effect;
    c.self_occlusion = effect != "SelfOcclusion off";
    c.rough_lobe = effect != "RoughLobe off";
    c.visitor_light = effect != "VisitorLight off";
    c.lobe_filter = effect != "AxisAlignedFilter off";
    c.still_frames = effect == "ProgressiveRefinement on" ? kRefinementStillFrames : 0;
    ours.push_back(c);
  }
  // A relic that samples its rough lobe: the default tracer without the axis-aligned filter, with
  // denser strata (the time the filter takes spent on samples instead).
  if (!o.effects_only &&
      std::any_of(scene.relic.materials.begin(), scene.relic.materials.end(), [&](const Material& m) {
        return m.roughness >= d.rough_interreflection_roughness &&
               m.roughness < reflect::kGlossyRoughnessLimit;
      })) {
    for (int grid : {6, 8}) {
      OursConfig off = default_tracer;
      off.lobe_filter = false;
      off.lobe_grid = grid;
      ours.push_back(off);
    }
  }
  // A glass relic: the refraction pass's knobs, around the default tracer.
  const bool transmissive = std::any_of(scene.relic.materials.begin(), scene.relic.materials.end(),
                                        [](const Material& m) { return m.transmission > 0.0f; });
  if (transmissive && !o.effects_only) {
    for (int depth : {1, 2, 4, 8, 16})
      ours.push_back({d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe, depth, 1.0f});
    for (float scale : {0.0f, 0.5f, 2.0f})
      ours.push_back({d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe, 0, scale});
    for (int stride : {1, 2, 3, 4})
      if (stride != d.refraction_stride)
        ours.push_back({d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe, 0, 1.0f, stride});
    for (int branch_rays : {0, 2, 16})
      ours.push_back({d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe, 0, 1.0f,
                      d.refraction_stride, branch_rays});
    for (float contrast : {0.0f, 4.0f, 8.0f, 16.0f})
      ours.push_back({d.aa_samples, d.pyramid_levels, d.grid.voxel_size, 0.0f, lobe, 0, 1.0f,
                      d.refraction_stride, d.refraction_branch_rays, contrast});
  }
  std::vector<int> ibl_levels = {6, 8, 10}, ssrt_rays = {1, 2, 4, 8, 16};
  int mcpt_steps = 0;
  for (int spp = 1; spp <= o.max_spp; spp *= 2) ++mcpt_steps;
  if (o.effects_only) {
    ibl_levels.clear();
    ssrt_rays.clear();
    mcpt_steps = 0;
  }
  ProgressReporter progress(std::int64_t(ours.size() + ibl_levels.size() + ssrt_rays.size()) + mcpt_steps,
                            "bench accuracy");
  for (const OursConfig& c : ours) {
    MethodSettings s = base;
    s.tracer.aa_samples = c.aa;
    s.tracer.pyramid_levels = c.levels;
    s.tracer.grid.voxel_size = c.voxel;
    s.tracer.evaluation.level_bias = c.bias;
    s.tracer.lobe_components = c.lobe_components;
    s.tracer.refraction_depth = c.refraction_depth;
    s.tracer.evaluation.transmitted_roughness_scale = c.transmitted_roughness_scale;
    s.tracer.refraction_stride = c.refraction_stride;
    s.tracer.refraction_branch_rays = c.refraction_branch_rays;
    s.tracer.refraction_supersample_contrast = c.refraction_supersample_contrast;
    s.tracer.evaluation.self_occlusion = c.self_occlusion;
    if (!c.rough_lobe) s.tracer.rough_interreflection_roughness = 2.0f;
    s.tracer.evaluation.visitor_light = c.visitor_light;
    s.tracer.evaluation.axis_aligned_filter = c.lobe_filter;
    s.tracer.rough_interreflection_grid = c.lobe_grid;
    s.still_frames = c.still_frames;
    std::string knob = "aa=" + std::to_string(c.aa) + " levels=" + std::to_string(c.levels) +
                       " voxel_cm=" + fmt(100 * c.voxel, 4) + " level_bias=" + fmt(c.bias, 2) +
                       " lobe=" + std::to_string(c.lobe_components);
    if (!c.effect.empty()) knob += " effect: " + c.effect;
    if (c.still_frames > 0) knob += " (" + std::to_string(c.still_frames) + " still frames)";
    if (!c.lobe_filter && c.effect.empty())
      knob += " lobe_filter=off lobe_grid=" + std::to_string(c.lobe_grid);
    if (transmissive)
      knob +=
          " internal_depth=" + (c.refraction_depth > 0 ? std::to_string(c.refraction_depth) : "measured") +
          " transmitted_lobe_scale=" + fmt(c.transmitted_roughness_scale, 2) +
          " refraction_stride=" + std::to_string(c.refraction_stride) +
          " branch_rays=" + std::to_string(c.refraction_branch_rays) +
          " supersample=" + fmt(c.refraction_supersample_contrast, 3);
    run("ours", knob, s, c.effect);
    progress.update();
  }
  for (int levels : ibl_levels) {
    MethodSettings s = base;
    s.ibl_levels = levels;
    run("ibl", "levels=" + std::to_string(levels), s, "");
    progress.update();
  }
  for (int rays : ssrt_rays) {
    MethodSettings s = base;
    s.spp = rays;
    run("ssrt", "rays=" + std::to_string(rays), s, "");
    progress.update();
  }
  if (!o.effects_only) {  // path tracing of the voxels plus panorama: one progressive render, the sampling
                          // time per spp
    const ReconstructedScene reconstruction(scene, reflect::VoxelGridSettings{}, true, 7);
    reference::ProgressiveRender render(reconstruction.tracer, camera);
    double sampling_ms = 0;
    for (int spp = 1; spp <= o.max_spp; spp *= 2) {
      const Stopwatch pass;
      render.addSamples(spp - render.samplesPerPixel());
      sampling_ms += pass.ms();
      AccuracyPoint p{"mcpt", "spp=" + std::to_string(spp), "", "", sampling_ms, 0, 0, false};
      score(p, render.image());
      points.push_back(p);
      progress.update();
    }
  }
  progress.done();
  markPareto(points);
  return sweep;
}

std::string accuracySvg(const std::vector<AccuracyPoint>& points, const std::string& title) {
  LogLogPlot plot{title, "ms per view (frame work / 4 included)", "fg_mse", "filled: Pareto front", 720, 460,
                  {}};
  // The front: the Pareto points in time order, joined.
  std::vector<const AccuracyPoint*> front;
  for (const AccuracyPoint& p : points)
    if (p.pareto) front.push_back(&p);
  std::sort(front.begin(), front.end(),
            [](const AccuracyPoint* a, const AccuracyPoint* b) { return a->ms < b->ms; });
  PlotSeries front_line{"Pareto front", "#888", {}, true, true, 0, false};
  for (const AccuracyPoint* p : front) front_line.markers.push_back({p->ms, p->fg_mse, "", true});
  plot.series.push_back(std::move(front_line));
  const std::vector<std::pair<std::string, std::string>> colours = {
      {"ours", "#000000"}, {"ibl", "#d62728"}, {"ssrt", "#9467bd"}, {"mcpt", "#1f77b4"}};
  for (const auto& [method, colour] : colours) {
    PlotSeries series{method, colour, {}, false, false, 3.5, true};
    for (const AccuracyPoint& p : points)
      if (p.method == method)
        series.markers.push_back(
            {p.ms, p.fg_mse,
             p.method + " " + p.knob + ": " + fmt(p.ms, 3) + " ms, fg_mse " + fmt(p.fg_mse, 3), p.pareto});
    plot.series.push_back(std::move(series));
  }
  return svgOf(plot);
}

std::string effectsSvg(const std::vector<SceneSweep>& sweeps, const std::string& title) {
  LogLogPlot plot{title,
                  "ms per view (frame work / 4 included)",
                  "mse, whole view",
                  "segment: default -> effect switched",
                  760,
                  480,
                  {}};
  const std::vector<std::pair<std::string, std::string>> colours = {{"SelfOcclusion off", "#d62728"},
                                                                    {"RoughLobe off", "#ff7f0e"},
                                                                    {"VisitorLight off", "#2ca02c"},
                                                                    {"AxisAlignedFilter off", "#9467bd"},
                                                                    {"ProgressiveRefinement on", "#1f77b4"}};
  PlotSeries defaults{"default tracer", "#000000", {}, false, false, 3.5, true};
  for (const SceneSweep& s : sweeps)
    if (const AccuracyPoint* d = effectPoint(s.sweep, "default"))
      defaults.markers.push_back(
          {d->ms, d->mse, sceneName(s.options) + " default: " + fmt(d->ms, 3) + " ms, mse " + fmt(d->mse, 3),
           true});
  for (const auto& [effect, colour] : colours) {
    bool first = true;
    for (const SceneSweep& s : sweeps) {
      const AccuracyPoint* d = effectPoint(s.sweep, "default");
      const AccuracyPoint* v = effectPoint(s.sweep, effect);
      if (!d || !v) continue;
      PlotSeries segment{effect, colour, {}, true, false, 3.0, first};
      segment.markers.push_back({d->ms, d->mse, "", true});
      segment.markers.push_back(
          {v->ms, v->mse,
           sceneName(s.options) + " " + effect + ": " + fmt(v->ms, 3) + " ms, mse " + fmt(v->mse, 3), false});
      plot.series.push_back(std::move(segment));
      first = false;
    }
  }
  plot.series.push_back(std::move(defaults));
  return svgOf(plot);
}

std::string effectsTable(const std::vector<SceneSweep>& sweeps) {
  std::ostringstream md;
  md << "| scene | effect | in the plan | ms without | ms with | mse without | mse with | mse without / with "
        "|\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const SceneSweep& s : sweeps) {
    const AccuracyPoint* d = effectPoint(s.sweep, "default");
    if (!d) continue;
    for (const std::string& effect : effectVariants()) {
      const AccuracyPoint* v = effectPoint(s.sweep, effect);
      if (!v || v == d) continue;
      // "X off" switches an effect of the default off; "X on" adds one to it.
      const bool adds = effect.size() > 3 && effect.compare(effect.size() - 3, 3, " on") == 0;
      const AccuracyPoint& with = adds ? *v : *d;
      const AccuracyPoint& without = adds ? *d : *v;
      const std::string pass = effect.substr(0, effect.rfind(' '));
      // The rough lobe is a part of StaticReflections, not a pass of its own.
      const std::string passes = with.plan.substr(0, with.plan.find(" ("));
      const std::string planned = pass == "RoughLobe"                                                ? "-"
                                  : ("," + passes + ",").find("," + pass + ",") != std::string::npos ? "yes"
                                                                                                     : "no";
      md << "| " << sceneName(s.options) << " | " << pass << " | " << planned << " | " << fmt(without.ms, 3)
         << " | " << fmt(with.ms, 3) << " | " << fmt(without.mse, 3) << " | " << fmt(with.mse, 3) << " | "
         << (with.mse > 0 ? fmt(without.mse / with.mse, 3) : "-") << " |\n";
    }
  }
  return md.str();
}

std::string accuracyCsv(const AccuracyOptions& o, const AccuracySweep& sweep) {
  std::ostringstream csv;
  csv << "hall,relic,size,gt_spp,fg_pixels,method,knob,effect,ms,fg_mse,mse,pareto\n";
  for (const AccuracyPoint& p : sweep.points)
    csv << o.hall << "," << o.relic << "," << o.size << "," << o.gt_spp << "," << sweep.region_pixels << ","
        << p.method << ",\"" << p.knob << "\"," << p.effect << "," << p.ms << "," << p.fg_mse << "," << p.mse
        << "," << p.pareto << "\n";
  return csv.str();
}

}  // namespace holo::eval
