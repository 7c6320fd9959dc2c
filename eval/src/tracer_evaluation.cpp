#include "holo/eval/tracer_evaluation.hpp"

#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/eval/ground_truth_cache.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/eval/scoring.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reference/voxel_emitters.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::eval {
namespace {

struct Scorer {
  const ForegroundScoring& scoring;
  void operator()(Entry& e) const {
    e.mse = scoring.mse(e.image);
    e.fg_mse = scoring.foregroundMse(e.image);
  }
};

// Runs a method `repeats` times: the first run's image, the median time.
Entry timed(const std::string& method, const std::string& knob, const ReflectionScene& scene,
            const CameraModel& camera, const MethodSettings& s, int repeats,
            std::vector<std::vector<std::pair<std::string, double>>>* passes = nullptr) {
  Entry e;
  e.method = method;
  e.knob = knob;
  std::vector<double> frame, view;
  for (int i = 0; i < repeats; ++i) {
    MethodResult r = renderMethod(method == "ibl_static" ? "ibl" : method, scene, camera, s);
    if (method == "ours") {
      frame.push_back(r.frame_ms);
      view.push_back(r.view_ms);
    } else {  // ibl-baseline: the map build is per frame; the rest (and every other method) per view
      frame.push_back(r.build_ms);
      view.push_back(r.ms - r.build_ms);
    }
    if (passes) passes->push_back(r.passes);
    if (i == 0) e.image = r.image;
  }
  e.frame_ms = median(frame);
  e.view_ms = median(view);
  e.ms = e.view_ms + e.frame_ms / kViewsPerFrame;
  return e;
}

}  // namespace

SceneResult evaluateTracerScene(const std::string& hall, const std::string& relic,
                                const TracerEvalOptions& o) {
  SceneResult res;
  res.hall = hall;
  res.relic = relic;
  const VisitorScene setup = visitorScene(hall, relic, o.close_visitors, o.camera_tilt_deg, o.camera_vfov_deg,
                                          o.size, o.visitor_model, o.panorama_at_infinity);
  const ReflectionScene& scene = setup.scene;
  const CameraModel& camera = setup.camera;
  const VisitorView& pick = setup.pick;
  res.frame = pick.frame;
  res.face = pick.face;
  res.reflected_fraction = pick.reflected_fraction;
  res.seen_through_fraction = pick.seen_through_fraction;
  res.foreground_points = scene.foreground.points.size();
  HOLO_LOG_INFO("eval tracer: {} x {}, frame {}, face {}", hall, relic, pick.frame, pick.face);

  const cv::Mat gt_hdr = cachedGroundTruth(scene, camera, o.gt_spp, true, o.cache);
  // Compared as the pyramid displays them: tone-mapped at the ground truth's exposure, sRGB.
  const ForegroundScoring scoring =
      foregroundScoring(gt_hdr, cachedGroundTruth(scene, camera, o.gt_spp, false, o.cache), o.fg_threshold);
  const float exposure = scoring.exposure;
  const cv::Mat& region = scoring.region;
  res.fg_pixels = scoring.region_pixels;
  const Scorer score{scoring};
  // The truth at N spp is the mean of its first N/4 samples (the truth at N/4) and 3N/4 more: their
  // squared difference has 3 times the variance of the truth's noise.
  if (o.gt_spp >= 4 && res.fg_pixels > 0)
    res.gt_noise = scoring.foregroundMse(cachedGroundTruth(scene, camera, o.gt_spp / 4, true, o.cache)) / 3.0;

  MethodSettings base;
  base.static_ibl = staticIbl(scene, base);
  base.tracer = o.tracer;
  base.tracer.relic_interreflection = !o.no_interreflection;

  // ours and the IBL at ours' anti-aliasing (the same renderer with no foreground: the same hit
  // points, static shading and tone map, no grid, pyramids, walk or composition), timed
  // alternately so that the load of the shared machine falls on both alike. The per-pass medians
  // say where ours' time goes.
  std::vector<std::vector<std::pair<std::string, double>>> passes;
  MethodSettings no_visitors = base;
  no_visitors.with_visitors = false;
  const std::string ours_knob = "aa=" + std::to_string(base.tracer.aa_samples) +
                                ",levels=" + std::to_string(base.tracer.pyramid_levels) +
                                (base.tracer.relic_interreflection ? "" : ",no-bounce");
  Entry ours, ibl_same_aa;
  {
    std::vector<Entry> a, b;
    for (int i = 0; i < o.repeats; ++i) {
      a.push_back(timed("ours", ours_knob, scene, camera, base, 1, &passes));
      b.push_back(timed("ours", ours_knob, scene, camera, no_visitors, 1));
    }
    const auto combine = [](std::vector<Entry>& runs, const std::string& name) {
      Entry e = runs.front();
      e.method = name;
      std::vector<double> f, v;
      for (const Entry& r : runs) f.push_back(r.frame_ms), v.push_back(r.view_ms);
      e.frame_ms = median(f);
      e.view_ms = median(v);
      e.ms = e.view_ms + e.frame_ms / kViewsPerFrame;
      return e;
    };
    ours = combine(a, "ours");
    ibl_same_aa = combine(b, "ibl_same_aa");
  }
  score(ours);
  score(ibl_same_aa);
  if (!passes.empty())
    for (std::size_t p = 0; p < passes.front().size(); ++p) {
      std::vector<double> v;
      for (const auto& run : passes)
        if (p < run.size()) v.push_back(run[p].second);
      res.ours_passes.emplace_back(passes.front()[p].first, median(v));
    }
  res.entries.push_back(ours);
  res.entries.push_back(ibl_same_aa);

  // A glass relic's two references: the same renderer with the glass shaded as opaque, and with
  // its refraction reading the IBL only (no visitors seen through it).
  const bool glass = std::any_of(scene.relic.materials.begin(), scene.relic.materials.end(),
                                 [](const Material& m) { return m.transmissive(); });
  if (glass && base.tracer.evaluation.refraction_enabled) {
    MethodSettings opaque = base;
    opaque.tracer.evaluation.refraction_enabled = false;
    Entry e = timed("ours", ours_knob + ",no-refraction", scene, camera, opaque, o.repeats);
    e.method = "ours_glass_opaque";
    score(e);
    res.entries.push_back(e);
    if (base.tracer.evaluation.refracted_foreground) {
      MethodSettings ibl_only = base;
      ibl_only.tracer.evaluation.refracted_foreground = false;
      e = timed("ours", ours_knob + ",no-refracted-foreground", scene, camera, ibl_only, o.repeats);
      e.method = "ours_ibl_refraction";
      score(e);
      res.entries.push_back(e);
    }
  }

  Entry ibl = timed("ibl-baseline", "levels=9,samples=64", scene, camera, base, std::max(1, o.repeats / 2));
  ibl.method = "ibl";
  score(ibl);
  res.entries.push_back(ibl);
  Entry ibl_static =
      timed("ibl_static", "levels=9,samples=64 (map prebuilt)", scene, camera, base, o.repeats);
  score(ibl_static);
  res.entries.push_back(ibl_static);

  // ssrt at equal time: double the rays per hit point while the time stays within ours'.
  Entry ssrt;
  for (int rays = o.ssrt_rays > 0 ? o.ssrt_rays : 1; rays <= std::max(64, o.ssrt_rays); rays *= 2) {
    MethodSettings s = base;
    s.spp = rays;
    Entry e = timed("ssrt", "rays=" + std::to_string(rays), scene, camera, s, std::max(1, o.repeats / 2));
    if (rays > 1 && e.ms > ours.ms && o.ssrt_rays == 0) break;
    ssrt = e;
    if (o.ssrt_rays > 0) break;
  }
  score(ssrt);
  res.entries.push_back(ssrt);

  // The reconstructed scene for MCPT: the voxel grid ours walks, as emitting cubes.
  const Stopwatch build_time;
  const ReconstructedScene reconstruction(scene, o.tracer.grid, true, 7);  // seed independent of the truth's
  const reference::PathTracer& tracer = reconstruction.tracer;
  const double build_ms = build_time.ms();

  res.mcpt_build_ms = build_ms;
  {  // equal time: whole samples per pixel while the sampling time stays within ours' time
    reference::ProgressiveRender render(tracer, camera);
    const Stopwatch sampling;
    double spent = 0;
    do {
      render.addSamples(1);
      spent = sampling.ms();
    } while (spent + spent / render.samplesPerPixel() <= ours.ms);
    Entry e;
    e.method = "mcpt_equal_time";
    e.knob = "spp=" + std::to_string(render.samplesPerPixel());
    e.ms = e.view_ms = spent;
    e.image = render.image();
    score(e);
    res.entries.push_back(e);
  }
  {  // equal quality: 1, 2, 4, ... spp until fg_mse <= ours'
    reference::ProgressiveRender render(tracer, camera);
    double sampling_ms = 0;
    Entry e;
    e.method = "mcpt_equal_quality";
    e.reached = false;
    std::map<int, double> fg_mse_at_spp;
    for (int spp = 1; spp <= o.mcpt_max_spp; spp *= 2) {
      const Stopwatch pass;
      render.addSamples(spp - render.samplesPerPixel());
      sampling_ms += pass.ms();  // scoring between passes is not the renderer's time
      e.image = render.image();
      score(e);
      fg_mse_at_spp[spp] = e.fg_mse;
      if (res.fg_pixels == 0 || e.fg_mse <= ours.fg_mse) {
        e.reached = true;
        break;
      }
    }
    e.ms = e.view_ms = sampling_ms;
    e.knob = "spp=" + std::to_string(render.samplesPerPixel()) + (e.reached ? "" : " (not reached)");
    res.entries.push_back(e);
    // The reconstruction floor: the same samples run on to floor_spp. Path tracing's fg_mse is
    // floor + variance / spp, so from N/4 and N spp the floor is (4 fg_mse(N) - fg_mse(N/4)) / 3.
    if (o.floor_spp >= 4 && res.fg_pixels > 0) {
      for (const int spp : {o.floor_spp / 4, o.floor_spp}) {
        if (fg_mse_at_spp.count(spp)) continue;
        if (render.samplesPerPixel() > spp) break;  // already beyond it: not measurable
        render.addSamples(spp - render.samplesPerPixel());
        Entry at;
        at.image = render.image();
        score(at);
        fg_mse_at_spp[spp] = at.fg_mse;
      }
      if (fg_mse_at_spp.count(o.floor_spp / 4) && fg_mse_at_spp.count(o.floor_spp))
        res.reconstruction_floor =
            std::max(0.0, (4.0 * fg_mse_at_spp[o.floor_spp] - fg_mse_at_spp[o.floor_spp / 4]) / 3.0);
    }
  }

  std::vector<cv::Mat> strip = {reflect::toneMap(gt_hdr, exposure)};
  for (const std::string m : {"ours", "ibl", "ssrt", "mcpt_equal_time", "mcpt_equal_quality"})
    strip.push_back(reflect::toneMap(res.at(m).image, exposure));
  cv::Mat region_bgr;
  cv::cvtColor(region, region_bgr, cv::COLOR_GRAY2BGR);
  strip.push_back(region_bgr);
  cv::hconcat(strip, res.strip);
  return res;
}

}  // namespace holo::eval
