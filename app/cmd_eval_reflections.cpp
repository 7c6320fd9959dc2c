// `holopyramid eval reflections`: what accuracy costs in time. Renders the ground truth (path
// traced, cached on disk by scene hash) with and without the visitors, then every method at a
// few quality settings, and reports for each (time, error) point the MSE over the whole view
// and over the dynamic-foreground reflection region (paper Sec. 4.1.2: the ground truths with
// and without the visitors differ by RGB distance >= 0.2). Writes JSON, CSV, an SVG plot of
// error against time and, with --images, each method's tone-mapped image, its error map and a
// side-by-side strip. HOLO_FULL_EVAL=1 (or --full) adds the slow, high-quality settings.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/reflect/image_metrics.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/eval/reflection_scene.hpp"

namespace holo::app {
namespace {

struct EvalOptions {
  SceneOptions scene;
  ViewOptions view;
  int gt_spp = 256;
  std::string json, csv, svg, images;
  std::string cache = (std::filesystem::temp_directory_path() / "holopyramid-gt-cache").string();
  bool full = false;
};

struct Point {
  std::string method, knob;
  MethodSettings settings;
  double ms = 0, mse = 0, fg_mse = 0;
  cv::Mat image;
};

// The (method, knob) points: the first of each method is its default (the one "methods" in the
// JSON reports); the rest trace the time/error curve.
std::vector<Point> plannedPoints(bool full, int gt_spp) {
  std::vector<Point> points;
  const auto add = [&](const std::string& method, const std::string& knob, MethodSettings s) {
    points.push_back({method, knob, s, 0, 0, 0, {}});
  };
  for (int spp : full ? std::vector<int>{16, 1, 4, 64, 256} : std::vector<int>{16, 1, 4}) {
    if (spp >= gt_spp) continue;
    MethodSettings s;
    s.spp = spp;
    s.seed = 7;  // independent of the ground truth's samples
    add("gt", "spp=" + std::to_string(spp), s);
  }
  const std::vector<std::pair<int, int>> ibl =
      full ? std::vector<std::pair<int, int>>{{10, 20}, {5, 8}, {10, 8}, {10, 40}, {17, 40}}
           : std::vector<std::pair<int, int>>{{10, 20}, {5, 8}};
  add("ours", "aa=4,levels=7", {});
  for (int rays : full ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4}) {
    MethodSettings s;
    s.spp = rays;
    add("ssrt", "rays=" + std::to_string(rays), s);
  }
  for (int spp : full ? std::vector<int>{4, 1, 16, 64, 256} : std::vector<int>{4, 1}) {
    MethodSettings s;
    s.spp = spp;
    s.seed = 7;
    add("mcpt", "spp=" + std::to_string(spp), s);
  }
  for (const std::string method : {"ibl", "ibl-baseline"})
    for (auto [levels, density] : ibl) {
      MethodSettings s;
      s.ibl_levels = levels;
      s.ibl_texel_density = density;
      add(method, "levels=" + std::to_string(levels) + ",density=" + std::to_string(density), s);
    }
  return points;
}

void writeCsv(const std::string& path, const std::vector<Point>& points) {
  std::ostringstream out;
  out << "method,knob,ms,mse,fg_mse\n";
  for (const Point& p : points)
    out << p.method << ",\"" << p.knob << "\"," << p.ms << "," << p.mse << "," << p.fg_mse << "\n";
  writeFileAtomically(path, out.str());
}

// Log-log plot of error (MSE, and foreground MSE dashed) against time per view.
void writeSvg(const std::string& path, const std::vector<Point>& points, const std::string& title) {
  LogLogPlot plot{title, "time per view (ms)", "MSE", "dashed: foreground MSE", 640, 420, {}};
  const std::vector<std::pair<std::string, std::string>> colours = {
      {"gt", "#1f77b4"},   {"ibl", "#2ca02c"},  {"ibl-baseline", "#d62728"},
      {"ours", "#000000"}, {"ssrt", "#9467bd"}, {"mcpt", "#ff7f0e"}};
  for (const auto& [method, colour] : colours) {
    std::vector<const Point*> ps;
    for (const Point& p : points)
      if (p.method == method) ps.push_back(&p);
    if (ps.empty()) continue;
    std::sort(ps.begin(), ps.end(), [](const Point* a, const Point* b) { return a->ms < b->ms; });
    PlotSeries all{method, colour, {}, true, false, 3, true};
    PlotSeries foreground{method + " foreground", colour, {}, true, true, 3, false};
    for (const Point* p : ps) {
      all.markers.push_back({p->ms, p->mse, p->method + " " + p->knob, true});
      foreground.markers.push_back({p->ms, p->fg_mse, p->method + " " + p->knob + " (foreground)", true});
    }
    plot.series.push_back(std::move(all));
    plot.series.push_back(std::move(foreground));
  }
  writeFileAtomically(path, svgOf(plot));
}

int evalReflections(EvalOptions o) {
  if (const char* f = std::getenv("HOLO_FULL_EVAL"); f && std::string(f) == "1") o.full = true;
  const ReflectionScene scene = loadReflectionScene(o.scene);
  const CameraModel camera = viewCamera(o.view, scene);
  const cv::Mat gt = cachedGroundTruth(scene, camera, o.gt_spp, true, o.cache);
  cv::Mat region(gt.size(), CV_8UC1, cv::Scalar(0));
  if (!scene.visitors.meshes.empty())
    region = reflect::foregroundRegion(gt, cachedGroundTruth(scene, camera, o.gt_spp, false, o.cache));
  const int fg_pixels = cv::countNonZero(region);

  std::vector<Point> points = plannedPoints(o.full, o.gt_spp);
  for (Point& p : points) {
    const MethodResult r = renderMethod(p.method, scene, camera, p.settings);
    p.ms = r.ms;
    p.image = r.image;
    p.mse = reflect::mse(r.image, gt);
    p.fg_mse = fg_pixels > 0 ? reflect::mse(r.image, gt, region) : 0.0;
    std::cout << p.method << " " << p.knob << ": " << p.ms << " ms, mse " << p.mse << ", fg_mse " << p.fg_mse
              << "\n";
  }

  nlohmann::json j;
  j["scene"] = scene.scene_name;
  j["relic"] = scene.relic_name;
  j["width"] = camera.width();
  j["height"] = camera.height();
  j["gt_spp"] = o.gt_spp;
  j["fg_pixels"] = fg_pixels;
  j["methods"] = nlohmann::json::object();
  j["points"] = nlohmann::json::array();
  for (const Point& p : points) {
    const nlohmann::json entry = {{"fg_mse", p.fg_mse}, {"mse", p.mse}, {"ms", p.ms}, {"knob", p.knob}};
    if (!j["methods"].contains(p.method)) j["methods"][p.method] = entry;
    nlohmann::json point = entry;
    point["method"] = p.method;
    j["points"].push_back(point);
  }
  if (!o.json.empty())
    writeFileAtomically(o.json, j.dump(2) + "\n");
  else
    std::cout << j.dump(2) << "\n";
  if (!o.csv.empty()) writeCsv(o.csv, points);
  if (!o.svg.empty())
    writeSvg(o.svg, points,
             "Reflections: error vs time (" + scene.scene_name + ", " + scene.relic_name + ")");

  if (!o.images.empty()) {
    const std::filesystem::path dir = o.images;
    std::filesystem::create_directories(dir);
    const float exposure = reflect::autoExposure(gt);  // one exposure: images stay comparable
    std::vector<cv::Mat> strip = {reflect::toneMap(gt, exposure)};
    writePng(dir / "gt_reference.png", strip.front());
    cv::Mat region_bgr;
    cv::cvtColor(region, region_bgr, cv::COLOR_GRAY2BGR);
    writePng(dir / "foreground_region.png", region_bgr);
    std::map<std::string, bool> seen;
    for (const Point& p : points) {
      if (seen[p.method]) continue;  // the default setting of each method
      seen[p.method] = true;
      const cv::Mat ldr = reflect::toneMap(p.image, exposure);
      writePng(dir / (p.method + ".png"), ldr);
      writePng(dir / (p.method + "_error.png"), reflect::errorMap(p.image, gt));
      strip.push_back(ldr);
    }
    cv::Mat side_by_side;
    cv::hconcat(strip, side_by_side);
    writePng(dir / "side_by_side.png", side_by_side);
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval reflections",
    [](CLI::App& sub) {
      auto o = std::make_shared<EvalOptions>();
      o->scene.scene = "museum";
      o->view.width = o->view.height = 128;
      o->scene.addTo(sub);
      o->view.addTo(sub);
      sub.add_option("--gt-spp", o->gt_spp, "Ground-truth samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--json", o->json, "Write the results as JSON (default: stdout)");
      sub.add_option("--csv", o->csv, "Write every (time, error) point as CSV");
      sub.add_option("--svg", o->svg, "Write the error-vs-time plot as SVG");
      sub.add_option("--images", o->images, "Write tone-mapped images and error maps (PNG) here");
      sub.add_option("--cache", o->cache, "Ground-truth cache folder")->capture_default_str();
      sub.add_flag("--full", o->full, "All quality settings (slow); also HOLO_FULL_EVAL=1");
      return [o] { return evalReflections(*o); };
    },
    "Time and error of every reflection method against the path-traced ground truth"});

}  // namespace holo::app
