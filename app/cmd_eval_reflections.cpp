// `holopyramid eval reflections`: what accuracy costs in time (eval/method_sweep.hpp): every
// method at a few quality settings against the path-traced truth, each (time, error) point with
// the MSE over the whole view and over the dynamic-foreground reflection region. Writes JSON,
// CSV, an SVG plot of error against time and, with --images, each method's tone-mapped image,
// its error map and a side-by-side strip. HOLO_FULL_EVAL=1 (or --full) adds the slow,
// high-quality settings.
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
#include "holo/display/frame_output.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/eval/method_sweep.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reference/image_metrics.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::app {

using namespace holo::eval;
namespace {

struct EvalOptions {
  SceneOptions scene;
  ViewOptions view;
  int gt_spp = 256;
  std::string json, csv, svg, images;
  std::string cache = (std::filesystem::temp_directory_path() / "holopyramid-gt-cache").string();
  bool full = false;
};

void writeCsv(const std::string& path, const std::vector<MethodPoint>& points) {
  std::ostringstream out;
  out << "method,knob,ms,mse,fg_mse\n";
  for (const MethodPoint& p : points)
    out << p.method << ",\"" << p.knob << "\"," << p.ms << "," << p.mse << "," << p.fg_mse << "\n";
  writeFileAtomically(path, out.str());
}

// Log-log plot of error (MSE, and foreground MSE dashed) against time per view.
void writeSvg(const std::string& path, const std::vector<MethodPoint>& points, const std::string& title) {
  LogLogPlot plot{title, "time per view (ms)", "MSE", "dashed: foreground MSE", 640, 420, {}};
  const std::vector<std::pair<std::string, std::string>> colours = {
      {"gt", "#1f77b4"},   {"ibl", "#2ca02c"},  {"ibl-baseline", "#d62728"},
      {"ours", "#000000"}, {"ssrt", "#9467bd"}, {"mcpt", "#ff7f0e"}};
  for (const auto& [method, colour] : colours) {
    std::vector<const MethodPoint*> ps;
    for (const MethodPoint& p : points)
      if (p.method == method) ps.push_back(&p);
    if (ps.empty()) continue;
    std::sort(ps.begin(), ps.end(), [](const MethodPoint* a, const MethodPoint* b) { return a->ms < b->ms; });
    PlotSeries all{method, colour, {}, true, false, 3, true};
    PlotSeries foreground{method + " foreground", colour, {}, true, true, 3, false};
    for (const MethodPoint* p : ps) {
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
  const MethodSweep sweep = sweepMethods(scene, camera, o.full, o.gt_spp, o.cache);
  const cv::Mat& gt = sweep.truth;
  const cv::Mat& region = sweep.region;
  const int fg_pixels = sweep.region_pixels;
  const std::vector<MethodPoint>& points = sweep.points;
  for (const MethodPoint& p : points) {
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
  for (const MethodPoint& p : points) {
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
    display::writePngAtomically(dir / "gt_reference.png", strip.front());
    cv::Mat region_bgr;
    cv::cvtColor(region, region_bgr, cv::COLOR_GRAY2BGR);
    display::writePngAtomically(dir / "foreground_region.png", region_bgr);
    std::map<std::string, bool> seen;
    for (const MethodPoint& p : points) {
      if (seen[p.method]) continue;  // the default setting of each method
      seen[p.method] = true;
      const cv::Mat ldr = reflect::toneMap(p.image, exposure);
      display::writePngAtomically(dir / (p.method + ".png"), ldr);
      display::writePngAtomically(dir / (p.method + "_error.png"), reference::errorMap(p.image, gt));
      strip.push_back(ldr);
    }
    cv::Mat side_by_side;
    cv::hconcat(strip, side_by_side);
    display::writePngAtomically(dir / "side_by_side.png", side_by_side);
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
      addSceneOptions(sub, o->scene);
      addViewOptions(sub, o->view);
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
