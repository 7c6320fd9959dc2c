// `holopyramid eval depth`: runs the simulated museum through the pull-push temporal depth filter
// and its baselines (raw, temporal median, TAA) and reports the paper's Table 2 metrics as JSON
// (docs/depthfilter.md); --images writes a Fig. 9-like picture of each method's point cloud.
// `--recording DIR` instead runs a recording without truth (ours from `holopyramid simulate`, a
// TUM sequence folder) through the product's foreground pipeline and reports what can be measured
// without it (holo/eval/depth_stability.hpp); --images writes depth_stability.png. Next to the
// depth metrics it reports the relic's displayed reflection flicker with each method's depth fed
// through the live renderer (--images: reflection_flicker.png).
#include <filesystem>
#include <iostream>
#include <vector>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/mask_depth_growth.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/eval/depth_recording_evaluation.hpp"
#include "holo/eval/simulated_depth_evaluation.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;

struct Options {
  std::string scene = "museum";
  std::string visitor_model;  // empty: the scene's own
  int frames = 60;
  int width = 0;
  int height = 0;
  int learning_frames = depthfilter::TemporalDepthFilterConfig{}.learning_frames;
  int levels = depthfilter::TemporalDepthFilterConfig{}.levels;
  std::vector<int> compared_levels = eval::SimulatedDepthOptions{}.compared_levels;
  bool mask_persistence = eval::SimulatedDepthOptions{}.mask_persistence;
  bool cross_camera = eval::SimulatedDepthOptions{}.cross_camera;
  bool round_trip_check = eval::SimulatedDepthOptions{}.round_trip_check;
  bool reflection_flicker = eval::SimulatedDepthOptions{}.reflection_flicker;
  int view_size = eval::SimulatedDepthOptions{}.view_size;
  bool keep_attached_limbs = eval::SimulatedDepthOptions{}.keep_attached_limbs;
  int foreground_scale = eval::SimulatedDepthOptions{}.foreground_scale;
  bool full_size_outline = eval::SimulatedDepthOptions{}.full_size_outline;
  bool fill_mask_edge = eval::SimulatedDepthOptions{}.fill_mask_edge;
  bool fill_on_precursor_surface = eval::SimulatedDepthOptions{}.fill_on_precursor_surface;
  int mask_growth_steps = eval::SimulatedDepthOptions{}.mask_growth_steps;
  bool fill_witnessed = eval::SimulatedDepthOptions{}.fill_witnessed;
  std::string json;
  std::string images;
  std::string recording;
  int background_frames = 8;
};

// DIR/NAME, then its path on stderr.
void writeFigure(const fs::path& dir, const std::string& name, const cv::Mat& figure) {
  fs::create_directories(dir);
  const fs::path path = dir / name;
  display::writePngAtomically(path, figure);
  std::cerr << "wrote " << path.string() << "\n";
}

int runRecording(const Options& o) {
  if (o.background_frames < 0)
    throw InputError("", "--background-frames", "a number of frames >= 0",
                     std::to_string(o.background_frames));
  const eval::DepthRecordingEvaluation e =
      eval::evaluateDepthRecording({o.recording, o.learning_frames, o.background_frames, !o.images.empty()});
  std::cout << e.report.dump(2) << "\n";
  if (!o.json.empty()) writeFileAtomically(o.json, e.report.dump(2) + "\n");
  if (!o.images.empty()) writeFigure(o.images, "depth_stability.png", e.figure);
  return 0;
}

int run(const Options& o) {
  if (o.learning_frames < 0)
    throw InputError("", "--learning-frames", "a number of frames >= 0", std::to_string(o.learning_frames));
  if (!o.recording.empty()) return runRecording(o);
  if (o.frames < 1) throw InputError("", "--frames", "a number of frames >= 1", std::to_string(o.frames));
  const int max_levels = depthfilter::TemporalDepthFilterConfig::kMaxLevels;
  for (int levels : o.compared_levels)
    if (levels < 1 || levels > max_levels)
      throw InputError("", "--compare-levels", "levels in [1, " + std::to_string(max_levels) + "]",
                       std::to_string(levels));
  if (o.view_size < 0 || o.view_size > 4096)
    throw InputError("", "--view-size", "0 (the live loop's) or 1..4096 pixels", std::to_string(o.view_size));
  if (o.foreground_scale < 1 || o.foreground_scale > depthfilter::kMaxForegroundScale)
    throw InputError("", "--foreground-scale",
                     "an integer in [1, " + std::to_string(depthfilter::kMaxForegroundScale) + "]",
                     std::to_string(o.foreground_scale));
  if (o.mask_growth_steps < 0 || o.mask_growth_steps > depthfilter::MaskDepthGrowthConfig::kMaxSteps)
    throw InputError(
        "", "--mask-growth-steps",
        "an integer in [0, " + std::to_string(depthfilter::MaskDepthGrowthConfig::kMaxSteps) + "]",
        std::to_string(o.mask_growth_steps));
  if (o.levels < 1 || o.levels > max_levels)
    throw InputError("", "--levels", "l_max in [1, " + std::to_string(max_levels) + "]",
                     std::to_string(o.levels));
  const eval::SimulatedDepthEvaluation e = eval::evaluateSimulatedDepth({o.scene,
                                                                         o.visitor_model,
                                                                         o.frames,
                                                                         o.width,
                                                                         o.height,
                                                                         o.learning_frames,
                                                                         o.levels,
                                                                         o.compared_levels,
                                                                         !o.images.empty(),
                                                                         o.mask_persistence,
                                                                         o.cross_camera,
                                                                         o.round_trip_check,
                                                                         o.reflection_flicker,
                                                                         o.view_size,
                                                                         o.keep_attached_limbs,
                                                                         o.foreground_scale,
                                                                         o.full_size_outline,
                                                                         o.fill_mask_edge,
                                                                         o.fill_on_precursor_surface,
                                                                         o.mask_growth_steps,
                                                                         o.fill_witnessed});
  std::cout << e.report.dump(2) << "\n";
  std::cerr << eval::depthMetricsTable(e.rows);
  std::cerr << "\n" << e.coverage_table;
  if (!e.flicker_rows.empty()) std::cerr << "\n" << eval::reflectionFlickerTable(e.flicker_rows);
  if (!o.json.empty()) writeFileAtomically(o.json, e.report.dump(2) + "\n");
  if (!o.images.empty()) writeFigure(o.images, "depth_methods.png", e.figure);
  if (!o.images.empty() && !e.flicker_figure.empty())
    writeFigure(o.images, "reflection_flicker.png", e.flicker_figure);
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval depth",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.add_option("--scene", o->scene, "Built-in scene name or scene YAML file")->capture_default_str();
      sub.add_option("--frames", o->frames, "Scored frames after the learning frames")->capture_default_str();
      sub.add_option("--learning-frames", o->learning_frames, "Frames C that only learn the PDFs")
          ->capture_default_str();
      sub.add_option("--levels", o->levels, "Ours' pull-push levels l_max (1: no pull-push)")
          ->capture_default_str();
      sub.add_option("--compare-levels", o->compared_levels,
                     "Also run ours with each of these l_max on the same masks (each level's gain)")
          ->capture_default_str();
      sub.add_option("--mask-persistence", o->mask_persistence,
                     "Keep foreground the pixels without depth whose precursor was foreground and whose "
                     "colour still matches it (false: the mask without it)")
          ->capture_default_str();
      sub.add_option("--keep-attached-limbs", o->keep_attached_limbs,
                     "The mask's opening keeps the thin limbs joined to a body (false: the opening "
                     "removes them)")
          ->capture_default_str();
      sub.add_option("--fill-mask-edge", o->fill_mask_edge,
                     "Ours fills a hole at the mask's edge from the farthest measured neighbour of its "
                     "colour (false: it stays a hole)")
          ->capture_default_str();
      sub.add_option("--fill-on-precursor-surface", o->fill_on_precursor_surface,
                     "Ours fills a hole whose trusted precursor's colour neighbours span two surfaces from "
                     "those on the precursor's (false: it stays a hole)")
          ->capture_default_str();
      sub.add_option("--fill-witnessed", o->fill_witnessed,
                     "Ours fills a hole beside two surfaces of its colour with the one another camera "
                     "measured there (false: it stays a hole)")
          ->capture_default_str();
      sub.add_option("--mask-growth-steps", o->mask_growth_steps,
                     "The mask grows by up to this many pixels into readings whose background depth is "
                     "unknown and that continue its surface (0: it does not)")
          ->capture_default_str();
      sub.add_option("--cross-camera", o->cross_camera,
                     "The cameras fill each other's holes with their measured depth of the same visitor, "
                     "projected through the poses (false: each camera on its own)")
          ->capture_default_str();
      sub.add_option("--foreground-scale", o->foreground_scale,
                     "Every method on the camera frames reduced by this (1 or 2), scored at the camera's "
                     "resolution")
          ->capture_default_str();
      sub.add_option("--full-size-outline", o->full_size_outline,
                     "With --foreground-scale 2, ours' outline decided at the camera's resolution by its own "
                     "depth readings (false: each reduced pixel repeated over its block)")
          ->capture_default_str();
      sub.add_option("--flow-check", o->round_trip_check,
                     "The precursor flow's forward-backward check: a pixel whose precursor does not map "
                     "back to it (hidden in the previous frame) has none")
          ->capture_default_str();
      sub.add_option("--reflection-flicker", o->reflection_flicker,
                     "Also feed every method's depth through the live renderer and report the relic's "
                     "displayed reflection flicker (false: the depth metrics alone)")
          ->capture_default_str();
      sub.add_option("--view-size", o->view_size,
                     "Face view size of the reflection flicker (0: the live loop's)")
          ->capture_default_str();
      sub.add_option("--width", o->width, "Camera width (default: the scene's)");
      sub.add_option("--height", o->height, "Camera height (default: the scene's)");
      sub.add_option("--visitor-model", o->visitor_model,
                     "Visitors instead of the scene's: bodies (the default) or figures");
      sub.add_option("--json", o->json, "Write the report to this JSON file");
      sub.add_option(
          "--images", o->images,
          "Write depth_methods.png (Fig. 9-like; with --recording depth_stability.png) into this folder");
      sub.add_option("--recording", o->recording,
                     "Measure a recording without truth instead (holopyramid simulate's folder or a TUM "
                     "sequence): hole flicker, background noise, edge jitter");
      sub.add_option("--background-frames", o->background_frames,
                     "With --recording and no background/ folder: the first N frames are the empty room")
          ->capture_default_str();
      return [o] { return run(*o); };
    },
    "Temporal depth filter vs raw, median and TAA on a simulated scene (paper Table 2), or a recording "
    "without truth"});

}  // namespace holo::app
