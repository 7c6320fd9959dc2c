// `holopyramid eval reflections`: what accuracy costs in time (eval/method_sweep.hpp): every
// method at a few quality settings against the path-traced truth, each (time, error) point with
// the MSE over the whole view and over the dynamic-foreground reflection region. Writes JSON,
// CSV, an SVG plot of error against time and, with --images, each method's tone-mapped image,
// its error map and a side-by-side strip. HOLO_FULL_EVAL=1 (or --full) adds the slow,
// high-quality settings.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "holo/core/files.hpp"
#include "holo/eval/method_sweep.hpp"
#include "holo/eval/method_sweep_report.hpp"
#include "holo/eval/reflection_scene.hpp"

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

int evalReflections(EvalOptions o) {
  if (const char* f = std::getenv("HOLO_FULL_EVAL"); f && std::string(f) == "1") o.full = true;
  const ReflectionScene scene = loadReflectionScene(o.scene);
  const CameraModel camera = viewCamera(o.view, scene);
  const MethodSweep sweep = sweepMethods(scene, camera, o.full, o.gt_spp, o.cache);
  const std::vector<MethodPoint>& points = sweep.points;
  for (const MethodPoint& p : points) {
    std::cout << p.method << " " << p.knob << ": " << p.ms << " ms, mse " << p.mse << ", fg_mse " << p.fg_mse
              << "\n";
  }

  const nlohmann::json j = methodSweepJson(scene, camera, o.gt_spp, sweep);
  if (!o.json.empty())
    writeFileAtomically(o.json, j.dump(2) + "\n");
  else
    std::cout << j.dump(2) << "\n";
  if (!o.csv.empty()) writeMethodSweepCsv(o.csv, points);
  if (!o.svg.empty())
    writeMethodSweepSvg(o.svg, points,
                        "Reflections: error vs time (" + scene.scene_name + ", " + scene.relic_name + ")");

  if (!o.images.empty()) writeMethodSweepImages(o.images, sweep);
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
