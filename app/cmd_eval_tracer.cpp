// `holopyramid eval tracer`: issue 5's nine-scene evaluation, the paper's Table 1 extended with
// the baselines. For each hall x relic (visitors close to the pyramid: the frame and face where
// the relic's mirror rays meet the visitors most, reflection_setup.hpp's visitorView) it renders
// the path-traced ground truth with and without the visitors (cached on disk), then
//   ours                 the reflection tracer (FrameRenderer), median of --repeats runs;
//   ibl                  the paper's IBL: the foreground reprojected into the panorama around the
//                        relic and prefiltered again (it must be, every frame), then shaded;
//   ibl_static           the static hall's IBL alone, map built once, the shading per view;
//   ssrt                 screen-space ray tracing (reflect/ssrt.hpp) at the most rays per hit
//                        point whose time stays within ours' (equal time);
//   mcpt_equal_time      path tracing of the reconstructed scene (voxels plus panorama) for as
//                        many whole samples per pixel as fit in ours' time (at least 1); the
//                        Embree build of the voxel cubes (one geometry per voxel, slow) is
//                        reported apart and not counted, which favours the baseline;
//   mcpt_equal_quality   the same path tracer at 1, 2, 4, ... spp until its fg_mse is at most
//                        ours' (searched up to --mcpt-max-spp; "not reached" and the time there
//                        otherwise);
// and two floors that every fg_mse contains: the ground truth's own noise (from the truth at a
// quarter of its samples, which are the first quarter of its samples) and the reconstruction's
// error (the same path tracer run on to --floor-spp, extrapolated to infinitely many samples), and
// reports per scene and method the time (median ms per view), fg_mse and mse, the bars of the
// issue, a Markdown table, CSV, JSON, an SVG plot (fg_mse against time) and, per scene, a strip of
// the images (gt | ours | ibl | ssrt | mcpt_equal_time | mcpt_equal_quality).
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/depthfilter/voxel_grid.hpp"
#include "holo/reflect/image_metrics.hpp"
#include "holo/reflect/path_tracer.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/voxel_emitters.hpp"
#include "holo/sim/museum.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/eval/reflection_scene.hpp"

namespace holo::app {
namespace {

struct TracerEvalOptions {
  std::vector<std::string> halls = {"room", "gallery", "atrium"};
  std::vector<std::string> relics = {"vase", "kettle", "tripod"};
  int size = 96;
  int gt_spp = 1024;
  int mcpt_max_spp = 4096;
  int floor_spp = 4096;  // the reconstruction floor's path tracing; 0: not measured
  int repeats = 5;
  std::string out = "eval-tracer";
  std::string cache = (std::filesystem::temp_directory_path() / "holopyramid-gt-cache").string();
  bool require_fg_bars = false;
  // The paper's 0.2 leaves the region empty on the kettle and tripod: the visitors walk at >= 1.2 m
  // from the axis and those relics are rough (0.35, 0.6), so their reflections are soft; 0.05
  // gives them a region, mostly silhouette and grazing pixels (docs/tracer.md).
  float fg_threshold = reflect::kForegroundDistance;
  int ssrt_rays = 0;  // 0: the equal-time search; > 0: fixed (deterministic, for CI)
  // Visitors standing close to the pyramid (sim planCloseVisitors), besides the hall's walkers:
  // the "visitors close to the pyramid"; the walkers keep >= 1.2 m from the axis.
  int close_visitors = 1;
  // The depth cameras: the default rig (tilt 8, vfov 70) sees a visitor within ~0.6 m of the
  // pyramid only from the waist to the chest, and the relic mirrors the rest; tilt 20 with vfov 90
  // keeps the far visitors' feet (bottom edge -25 degrees, was -27) and sees the close ones' heads.
  float camera_tilt_deg = 20.0f;
  float camera_vfov_deg = 90.0f;
  // Ours' knobs (--aa, --levels, --level-bias, --voxel-size). 9 levels: with 7 the rough relics'
  // reads (kettle, 0.35) sat at the top level, blurred less than their lobe (docs/tracer.md).
  bool no_interreflection = false;  // ours without TracerSettings::relic_interreflection
  reflect::TracerSettings tracer = [] {
    reflect::TracerSettings t;
    t.pyramid_levels = 9;
    return t;
  }();
};

// Views a frame renders (one per pyramid face): the per-frame work is shared by this many.
constexpr int kViewsPerFrame = 4;

struct Entry {
  std::string method, knob;
  // ms: per view at frame time, = view_ms + frame_ms / kViewsPerFrame; frame_ms: the work done
  // once per frame for all views (ours: voxel grid + pyramids; ibl: reprojecting the visitors
  // into the panorama + prefiltering it); view_ms: the work per view.
  double ms = 0, mse = 0, fg_mse = 0;
  double frame_ms = 0, view_ms = 0;
  bool reached = true;  // mcpt_equal_quality: our fg_mse was reached
  cv::Mat image;
};

struct SceneResult {
  std::string hall, relic;
  int frame = 0, face = 0, fg_pixels = 0;
  float reflected_fraction = 0;  // of the relic's mirror rays meeting a visitor (the view pick)
  double mcpt_build_ms = 0;      // the voxel scene's Embree build, not in the mcpt times
  // Parts of every method's fg_mse that no renderer of the reconstructed foreground can remove
  // (both in fg_mse units, < 0: not measured): the ground truth's own noise, and the fg_mse of path
  // tracing the reconstruction (voxels plus panorama) extrapolated to infinitely many samples,
  // which contains that noise.
  double gt_noise = -1, reconstruction_floor = -1;
  std::vector<Entry> entries;
  std::vector<std::pair<std::string, double>> ours_passes;  // median ms per pass
  const Entry& at(const std::string& method) const {
    for (const Entry& e : entries)
      if (e.method == method) return e;
    throw Error("no entry " + method);
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// An HDR image as displayed: tone-mapped (Reinhard, sRGB) at one exposure, as floats in [0, 1]
// (CV_32FC3, so image_metrics' clamp leaves it as it is).
struct Display {
  float exposure;
  cv::Mat operator()(const cv::Mat& hdr) const { return displayedImage(hdr, exposure); }
};

struct Scorer {
  const cv::Mat& gt;  // displayed
  const cv::Mat& region;
  int fg_pixels;
  Display display;
  void operator()(Entry& e) const {
    const cv::Mat shown = display(e.image);
    e.mse = reflect::mse(shown, gt);
    e.fg_mse = fg_pixels > 0 ? reflect::mse(shown, gt, region) : 0.0;
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

SceneResult evalScene(const std::string& hall, const std::string& relic, const TracerEvalOptions& o) {
  SceneResult res;
  res.hall = hall;
  res.relic = relic;
  SceneOptions so;
  so.scene = hall;  // the built-in scene of that hall: its visitors
  so.hall = hall;
  so.relic = relic;
  so.close_visitors = o.close_visitors;
  so.camera_tilt_deg = o.camera_tilt_deg;
  so.camera_vfov_deg = o.camera_vfov_deg;
  const VisitorView pick = visitorView(so);
  so.frame = res.frame = pick.frame;
  res.face = pick.face;
  res.reflected_fraction = pick.reflected_fraction;
  const ReflectionScene scene = loadReflectionScene(so);
  ViewOptions vo;
  vo.width = vo.height = o.size;
  vo.face = pick.face;
  const CameraModel camera = viewCamera(vo, scene);
  std::cout << "== " << hall << " x " << relic << ": frame " << pick.frame << ", face " << pick.face << ", "
            << 100 * pick.reflected_fraction << "% of mirror rays meet a visitor, "
            << scene.foreground.points.size() << " foreground points" << std::endl;

  const cv::Mat gt_hdr = cachedGroundTruth(scene, camera, o.gt_spp, true, o.cache);
  // Compared as the pyramid displays them: tone-mapped at the ground truth's exposure, sRGB.
  const float exposure = reflect::autoExposure(gt_hdr);
  const Display display{exposure};
  const cv::Mat gt = display(gt_hdr);
  const cv::Mat region = reflect::foregroundRegion(
      gt, display(cachedGroundTruth(scene, camera, o.gt_spp, false, o.cache)), o.fg_threshold);
  res.fg_pixels = cv::countNonZero(region);
  const Scorer score{gt, region, res.fg_pixels, display};
  // The truth at N spp is the mean of its first N/4 samples (the truth at N/4) and 3N/4 more: their
  // squared difference has 3 times the variance of the truth's noise.
  if (o.gt_spp >= 4 && res.fg_pixels > 0)
    res.gt_noise =
        reflect::mse(display(cachedGroundTruth(scene, camera, o.gt_spp / 4, true, o.cache)), gt, region) /
        3.0;

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
  const auto t_build = std::chrono::steady_clock::now();
  depthfilter::VoxelGrid grid(o.tracer.grid);
  grid.build(scene.foreground);
  std::vector<Model> emitters;
  if (!grid.empty()) emitters.push_back(reflect::voxelEmitters(grid));
  const reflect::RenderScene rs(scene.relic, emitters);
  const reflect::Environment env(scene.panorama);
  reflect::PathTracerOptions po;
  po.seed = 7;  // independent of the ground truth's samples
  const reflect::PathTracer tracer(rs, env, po);
  const double build_ms = msSince(t_build);

  res.mcpt_build_ms = build_ms;
  {  // equal time: whole samples per pixel while the sampling time stays within ours' time
    reflect::ProgressiveRender render(tracer, camera);
    const auto t0 = std::chrono::steady_clock::now();
    double spent = 0;
    do {
      render.addSamples(1);
      spent = msSince(t0);
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
    reflect::ProgressiveRender render(tracer, camera);
    double sampling_ms = 0;
    Entry e;
    e.method = "mcpt_equal_quality";
    e.reached = false;
    std::map<int, double> fg_mse_at_spp;
    for (int spp = 1; spp <= o.mcpt_max_spp; spp *= 2) {
      const auto t_pass = std::chrono::steady_clock::now();
      render.addSamples(spp - render.samplesPerPixel());
      sampling_ms += msSince(t_pass);  // scoring between passes is not the renderer's time
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

  for (const Entry& e : res.entries)
    std::cout << "  " << std::left << std::setw(20) << e.method << std::setw(34) << e.knob << std::right
              << std::fixed << std::setprecision(1) << std::setw(9) << e.ms << " ms  fg_mse "
              << std::setprecision(5) << e.fg_mse << "  mse " << e.mse << std::defaultfloat << std::endl;
  if (res.gt_noise >= 0) std::cout << "  ground truth's noise in fg_mse " << res.gt_noise << std::endl;
  if (res.reconstruction_floor >= 0)
    std::cout << "  reconstruction floor (path tracing of the voxels, " << o.floor_spp
              << " spp extrapolated) fg_mse " << res.reconstruction_floor << std::endl;
  std::cout << "  ours passes:";
  for (const auto& [name, ms] : res.ours_passes) std::cout << " " << name << " " << ms;
  std::cout << " (ms)" << std::endl;

  const std::filesystem::path dir = std::filesystem::path(o.out) / "images";
  std::filesystem::create_directories(dir);
  std::vector<cv::Mat> strip = {reflect::toneMap(gt_hdr, exposure)};
  for (const std::string m : {"ours", "ibl", "ssrt", "mcpt_equal_time", "mcpt_equal_quality"})
    strip.push_back(reflect::toneMap(res.at(m).image, exposure));
  cv::Mat region_bgr;
  cv::cvtColor(region, region_bgr, cv::COLOR_GRAY2BGR);
  strip.push_back(region_bgr);
  cv::Mat row;
  cv::hconcat(strip, row);
  writePng(dir / (hall + "_" + relic + ".png"), row);
  return res;
}

std::string fmt(double v, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// fg_mse x 1e-2 as the paper's Table 1 with the ratios, then the times.
std::string markdownTable(const std::vector<SceneResult>& results, const TracerEvalOptions& o) {
  std::ostringstream s;
  s << "fg_mse x 1e-2 (paper Table 1 units) on the displayed images (tone-mapped at the ground truth's "
       "exposure, sRGB); "
    << o.size << "^2 views, gt " << o.gt_spp << " spp, " << o.close_visitors
    << " visitor(s) close to the pyramid, foreground region: displayed RGB distance >= " << o.fg_threshold
    << "\n\n"
    << "| scene | fg px | ours | ibl | ssrt | mcpt_et | ibl/ours | ssrt/ours | mcpt_et/ours | mcpt_eq spp | "
       "mcpt_eq/ours time | gt noise | recon floor |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SceneResult& r : results) {
    const Entry &ours = r.at("ours"), &ibl = r.at("ibl"), &ssrt = r.at("ssrt"), &et = r.at("mcpt_equal_time"),
                &eq = r.at("mcpt_equal_quality");
    const auto ratio = [&](double a) { return ours.fg_mse > 0 ? fmt(a / ours.fg_mse, 1) : std::string("-"); };
    s << "| " << r.hall << " x " << r.relic << " | " << r.fg_pixels << " | " << fmt(100 * ours.fg_mse, 3)
      << " | " << fmt(100 * ibl.fg_mse, 3) << " | " << fmt(100 * ssrt.fg_mse, 3) << " | "
      << fmt(100 * et.fg_mse, 3) << " | " << ratio(ibl.fg_mse) << " | " << ratio(ssrt.fg_mse) << " | "
      << ratio(et.fg_mse) << " | " << eq.knob.substr(4) << " | " << (eq.reached ? "" : ">")
      << fmt(eq.ms / ours.ms, 1) << " | " << (r.gt_noise >= 0 ? fmt(100 * r.gt_noise, 3) : "-") << " | "
      << (r.reconstruction_floor >= 0 ? fmt(100 * r.reconstruction_floor, 3) : "-") << " |\n";
  }
  s << "\ngt noise: the ground truth's own noise inside every fg_mse (from the truth at " << o.gt_spp / 4
    << " spp); recon floor: path tracing of the reconstructed scene (voxels plus panorama) extrapolated from "
    << o.floor_spp / 4 << " and " << o.floor_spp
    << " spp to infinitely many, the fg_mse of rendering the reconstruction exactly (it contains the gt "
       "noise).\n";
  s << "\nTimes, median ms. Per view at frame time = view + frame / " << kViewsPerFrame
    << " (the per-frame work is shared by the four face views). ibl_same_aa: the same renderer with no "
       "foreground (ours' hit points at the same anti-aliasing, static shading, tone map). ibl: the paper's "
       "IBL, frame = reprojecting the visitors into the panorama + prefiltering it, view = 1-sample shading. "
       "ibl_static: the prebuilt static map, 1-sample shading.\n\n"
    << "| scene | ours frame | ours view | ours per view | ibl_same_aa view | ours/ibl_same_aa view | ibl "
       "frame | "
       "ibl view | ibl per view | ours/ibl per view | ibl_static view | ssrt (rays) | mcpt_et (spp) | "
       "mcpt_eq (spp) |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SceneResult& r : results) {
    const Entry &ours = r.at("ours"), &same = r.at("ibl_same_aa"), &ibl = r.at("ibl"),
                &st = r.at("ibl_static"), &ssrt = r.at("ssrt"), &et = r.at("mcpt_equal_time"),
                &eq = r.at("mcpt_equal_quality");
    s << "| " << r.hall << " x " << r.relic << " | " << fmt(ours.frame_ms, 1) << " | " << fmt(ours.view_ms, 2)
      << " | " << fmt(ours.ms, 2) << " | " << fmt(same.view_ms, 2) << " | "
      << fmt(ours.view_ms / std::max(same.view_ms, 1e-9), 2) << " | " << fmt(ibl.frame_ms, 1) << " | "
      << fmt(ibl.view_ms, 2) << " | " << fmt(ibl.ms, 1) << " | " << fmt(ours.ms / std::max(ibl.ms, 1e-9), 2)
      << " | " << fmt(st.view_ms, 2) << " | " << fmt(ssrt.ms, 1) << " (" << ssrt.knob.substr(5) << ") | "
      << fmt(et.ms, 1) << " (" << et.knob.substr(4) << ") | " << fmt(eq.ms, 0) << " (" << eq.knob.substr(4)
      << ") |\n";
  }
  return s.str();
}

// The bars, one line each with the worst scene; returns whether the fg_mse bars against
// ibl and ssrt hold on every scene with a foreground region.
bool reportBars(const std::vector<SceneResult>& results, std::ostream& out) {
  struct Bar {
    explicit Bar(std::string w) : what(std::move(w)) {}
    std::string what;
    double worst = 1e30;
    std::string where;
    bool ok = true;
    int scenes = 0;
  };
  Bar ibl{"ours fg_mse <= ibl / 4 (ibl/ours >= 4)"}, ssrt{"ours fg_mse < ssrt's (ssrt/ours > 1)"},
      eq{"ours (per view) >= 10x faster than mcpt_equal_quality"},
      et{"ours fg_mse >= 4x lower than mcpt_equal_time (ours' per-view time)"},
      time_view{"ours per-view passes <= 1.1x ibl_same_aa's (ratio ibl/ours >= 0.91)"},
      time_ibl{"ours per view <= 1.1x the paper ibl's per view, frame work amortised (ratio >= 0.91)"};
  const auto check = [](Bar& b, double value, double bar, const std::string& where) {
    ++b.scenes;
    if (value < b.worst) b.worst = value, b.where = where;
    if (!(value >= bar)) b.ok = false;
  };
  for (const SceneResult& r : results) {
    const std::string where = r.hall + " x " + r.relic;
    const Entry& ours = r.at("ours");
    const Entry& eqe = r.at("mcpt_equal_quality");
    if (r.fg_pixels > 0 && ours.fg_mse > 0) {
      check(ibl, r.at("ibl").fg_mse / ours.fg_mse, 4.0, where);
      check(ssrt, r.at("ssrt").fg_mse / ours.fg_mse, 1.0 + 1e-9, where);
      check(et, r.at("mcpt_equal_time").fg_mse / ours.fg_mse, 4.0, where);
      check(eq, eqe.ms / ours.ms, 10.0, where + (eqe.reached ? "" : " (quality not reached)"));
    }
    check(time_view, r.at("ibl_same_aa").view_ms / ours.view_ms, 1.0 / 1.1, where);
    check(time_ibl, r.at("ibl").ms / ours.ms, 1.0 / 1.1, where);
  }
  // The fg_mse bars hold on "every one of the scenes": a scene without a foreground region (the
  // visitors change no displayed pixel by the threshold) cannot show them, so it fails them.
  for (const Bar* b : {&ibl, &ssrt, &eq, &et, &time_view, &time_ibl}) {
    const bool all = b->scenes == static_cast<int>(results.size());
    out << (b->ok && all ? "MET     " : "NOT MET ") << b->what << ": worst " << fmt(b->worst, 2) << " ("
        << b->where << ")";
    if (!all)
      out << "; " << (b->ok ? "holds on" : "measured on") << " the " << b->scenes << " of " << results.size()
          << " scenes with a foreground region";
    out << "\n";
  }
  // Where the paper's IBL is already within 4x of the reconstruction's floor, ours (which renders
  // the same reconstruction) could meet the 4x bar only by an error below the floor's.
  std::string below;
  for (const SceneResult& r : results)
    if (r.fg_pixels > 0 && r.reconstruction_floor >= 0 && r.at("ibl").fg_mse / 4.0 < r.reconstruction_floor)
      below += (below.empty() ? "" : ", ") + r.hall + " x " + r.relic +
               " (ibl / 4 = " + fmt(100 * r.at("ibl").fg_mse / 4.0, 3) + ", floor " +
               fmt(100 * r.reconstruction_floor, 3) + ")";
  if (!below.empty())
    out << "        ibl / 4 is below the reconstruction floor (x 1e-2) on: " << below << "\n";
  return ibl.ok && ssrt.ok;
}

void writeOutputs(const std::vector<SceneResult>& results, const TracerEvalOptions& o,
                  const std::string& table, const std::string& bars) {
  const std::filesystem::path dir = o.out;
  std::filesystem::create_directories(dir);
  std::ostringstream csv;
  csv << "hall,relic,frame,face,fg_pixels,method,knob,ms,frame_ms,view_ms,fg_mse,mse,reached\n";
  nlohmann::json j = nlohmann::json::array();
  for (const SceneResult& r : results) {
    nlohmann::json sj = {{"hall", r.hall},
                         {"relic", r.relic},
                         {"frame", r.frame},
                         {"face", r.face},
                         {"fg_pixels", r.fg_pixels},
                         {"reflected_fraction", r.reflected_fraction},
                         {"mcpt_build_ms", r.mcpt_build_ms},
                         {"size", o.size},
                         {"gt_spp", o.gt_spp},
                         {"gt_noise", r.gt_noise},
                         {"reconstruction_floor", r.reconstruction_floor},
                         {"floor_spp", o.floor_spp}};
    for (const Entry& e : r.entries) {
      csv << r.hall << "," << r.relic << "," << r.frame << "," << r.face << "," << r.fg_pixels << ","
          << e.method << ",\"" << e.knob << "\"," << e.ms << "," << e.frame_ms << "," << e.view_ms << ","
          << e.fg_mse << "," << e.mse << "," << e.reached << "\n";
      sj["methods"][e.method] = {{"knob", e.knob},       {"ms", e.ms},         {"frame_ms", e.frame_ms},
                                 {"view_ms", e.view_ms}, {"fg_mse", e.fg_mse}, {"mse", e.mse},
                                 {"reached", e.reached}};
    }
    for (const auto& [name, ms] : r.ours_passes) sj["ours_passes_ms"][name] = ms;
    j.push_back(sj);
  }
  writeFileAtomically(dir / "results.csv", csv.str());
  writeFileAtomically(dir / "results.json", j.dump(2) + "\n");
  writeFileAtomically(dir / "table.md", table + "\n" + bars);

  // fg_mse against time, log-log, one marker per scene and method.
  LogLogPlot plot{
      "Foreground reflection MSE vs time per view (" + std::to_string(results.size()) + " scenes)",
      "time per view (ms)",
      "fg_mse",
      "hollow: quality not reached",
      680,
      440,
      {}};
  const std::vector<std::pair<std::string, std::string>> colours = {{"ours", "#000000"},
                                                                    {"ibl", "#d62728"},
                                                                    {"ibl_static", "#2ca02c"},
                                                                    {"ibl_same_aa", "#8c564b"},
                                                                    {"ssrt", "#9467bd"},
                                                                    {"mcpt_equal_time", "#ff7f0e"},
                                                                    {"mcpt_equal_quality", "#1f77b4"}};
  for (const auto& [method, colour] : colours) {
    PlotSeries series{method, colour, {}, false, false, 4, true};
    for (const SceneResult& r : results) {
      const Entry& e = r.at(method);
      series.markers.push_back(
          {e.ms, e.fg_mse, method + " " + r.hall + " x " + r.relic + " " + e.knob, e.reached});
    }
    plot.series.push_back(std::move(series));
  }
  writeFileAtomically(dir / "plot.svg", svgOf(plot));
}

int evalTracer(const TracerEvalOptions& o) {
  // Each hall is also the built-in scene that brings its visitors.
  for (const std::string& hall : o.halls)
    if (hall != "room" && hall != "gallery" && hall != "atrium")
      throw InputError("command line", "--halls", "room, gallery or atrium", hall);
  const std::vector<std::string> relics = sim::builtinRelicNames();
  for (const std::string& relic : o.relics)
    if (std::find(relics.begin(), relics.end(), relic) == relics.end())
      throw InputError("command line", "--relics", "built-in relics (vase, kettle, tripod, sphere)", relic);
  std::vector<SceneResult> results;
  for (const std::string& hall : o.halls)
    for (const std::string& relic : o.relics) results.push_back(evalScene(hall, relic, o));
  const std::string table = markdownTable(results, o);
  std::ostringstream bars;
  const bool fg_ok = reportBars(results, bars);
  std::cout << "\n" << table << "\n" << bars.str();
  writeOutputs(results, o, table, bars.str());
  std::cout << "wrote " << o.out << "/{table.md,results.csv,results.json,plot.svg,images/}\n";
  if (o.require_fg_bars && !fg_ok) {
    std::cerr << "the fg_mse bars (ours <= ibl / 4 and < ssrt) do not hold\n";
    return 1;
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval tracer",
    [](CLI::App& sub) {
      auto o = std::make_shared<TracerEvalOptions>();
      sub.add_option("--halls", o->halls, "Halls (room, gallery, atrium)")
          ->capture_default_str()
          ->delimiter(',');
      sub.add_option("--relics", o->relics, "Relics (vase, kettle, tripod, sphere)")
          ->capture_default_str()
          ->delimiter(',');
      sub.add_option("--size", o->size, "View width and height, pixels")
          ->capture_default_str()
          ->check(CLI::Range(8, 2048));
      sub.add_option("--gt-spp", o->gt_spp, "Ground-truth samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--mcpt-max-spp", o->mcpt_max_spp, "Largest spp of the equal-quality search")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 16));
      sub.add_option(
             "--floor-spp", o->floor_spp,
             "Path tracing of the reconstruction run to this spp (and a quarter of it) for its floor; 0: "
             "not measured")
          ->capture_default_str()
          ->check(CLI::Range(0, 1 << 16));
      sub.add_option("--repeats", o->repeats, "Runs per timing (the median is reported)")
          ->capture_default_str()
          ->check(CLI::Range(1, 100));
      sub.add_option("--out", o->out, "Output folder")->capture_default_str();
      sub.add_option("--fg-threshold", o->fg_threshold,
                     "Displayed RGB distance between the truths with and without visitors that makes a pixel "
                     "foreground (paper: 0.2)")
          ->capture_default_str()
          ->check(CLI::Range(0.001f, 1.0f));
      sub.add_option("--cache", o->cache, "Ground-truth cache folder")->capture_default_str();
      sub.add_option("--ssrt-rays", o->ssrt_rays, "SSRT rays per hit point; 0 = as many as fit in ours' time")
          ->capture_default_str()
          ->check(CLI::Range(0, 1024));
      sub.add_option("--close-visitors", o->close_visitors,
                     "Visitors standing close to the pyramid, reaching out to it, besides the hall's walkers")
          ->capture_default_str()
          ->check(CLI::Range(0, 4));
      sub.add_option("--camera-tilt-deg", o->camera_tilt_deg, "Depth cameras' upwards tilt, degrees")
          ->capture_default_str()
          ->check(CLI::Range(-60.0f, 60.0f));
      sub.add_option("--camera-vfov-deg", o->camera_vfov_deg,
                     "Depth cameras' vertical field of view, degrees")
          ->capture_default_str()
          ->check(CLI::Range(10.0f, 170.0f));
      sub.add_option("--aa", o->tracer.aa_samples, "Ours: sub-samples per pixel (1 or 4)")
          ->capture_default_str()
          ->check(CLI::IsMember({1, 4}));
      sub.add_option("--levels", o->tracer.pyramid_levels, "Ours: pyramid levels")
          ->capture_default_str()
          ->check(CLI::Range(1, reflect::kMaxPyramidLevels));
      sub.add_option("--level-bias", o->tracer.level_bias,
                     "Ours: added to the derived pyramid level (checks)")
          ->capture_default_str()
          ->check(CLI::Range(-8.0f, 8.0f));
      sub.add_option(
             "--lobe-components", o->tracer.lobe_components,
             "Ours: Gaussians per pyramid read standing for the GGX lobe (1: its Beckmann sigma; more: "
             "its heavy tail)")
          ->capture_default_str()
          ->check(CLI::Range(1, reflect::kMaxLobeComponents));
      sub.add_option("--foreground-map-width", o->tracer.foreground_map_width,
                     "Ours: texels around the rough foreground map (even)")
          ->capture_default_str()
          ->check(CLI::Range(8, 1024));
      sub.add_option("--rough-interreflection-grid", o->tracer.rough_interreflection_grid,
                     "Ours: side of the stratified lobe samples for the rough materials' "
                     "interreflection (1: the mirror ray; else even)")
          ->capture_default_str()
          ->check(CLI::IsMember({1, 2, 4, 6, 8}));
      sub.add_flag("!--no-rough-interleave", o->tracer.rough_interreflection_interleaved,
                   "Ours: every sample traces every lobe stratum of the rough interreflection "
                   "(not interleaved over 2x2 pixels)");
      sub.add_option(
             "--foreground-map-roughness", o->tracer.foreground_map_roughness,
             "Ours: from this roughness the foreground comes from the visitors prefiltered around the "
             "relic instead of the walk (> 1: never)")
          ->capture_default_str()
          ->check(CLI::Range(0.0f, 2.0f));
      sub.add_option(
             "--lobe-fallback-roughness", o->tracer.lobe_fallback_roughness,
             "Ours: from this roughness a ray that misses every voxel looks for the visitors within its "
             "lobe (> 1: never)")
          ->capture_default_str()
          ->check(CLI::Range(0.0f, 2.0f));
      sub.add_flag(
          "--no-interreflection", o->no_interreflection,
          "Ours: no bounce where a mirror ray meets the relic itself (the before of docs/tracer.md)");
      sub.add_option("--voxel-size", o->tracer.grid.voxel_size, "Ours: voxel size, metres")
          ->capture_default_str()
          ->check(CLI::Range(0.005f, 0.5f));
      sub.add_flag("--require-fg-bars", o->require_fg_bars,
                   "Exit 1 unless ours' fg_mse <= ibl's / 4 and < ssrt's on every scene");
      return [o] { return evalTracer(*o); };
    },
    "Issue 5's nine-scene table: ours, IBL, SSRT and path tracing at equal time and equal quality"});

}  // namespace holo::app
