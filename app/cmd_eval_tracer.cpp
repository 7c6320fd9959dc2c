// `holopyramid eval tracer`: the nine-scene evaluation (the paper's Table 1 extended with the
// baselines, eval/tracer_evaluation.hpp) over --halls x --relics; prints each scene's methods as
// it finishes, then the bars, a Markdown table, and writes CSV, JSON, an SVG plot (fg_mse against
// time) and, per scene, a strip of the images (gt | ours | ibl | ssrt | mcpt_equal_time |
// mcpt_equal_quality | the foreground region).
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/eval/tracer_evaluation.hpp"
#include "holo/eval/tracer_report.hpp"
#include "holo/relics/relics.hpp"
#include "holo/sim/museum.hpp"

namespace holo::app {

using namespace holo::eval;
namespace {

struct TracerEvalCommand {
  TracerEvalOptions eval;
  std::string out = "eval-tracer";
  bool require_fg_bars = false;
};

// One scene's methods as it finishes, and its strip of images into OUT/images.
void reportScene(const SceneResult& res, const TracerEvalCommand& command) {
  const TracerEvalOptions& o = command.eval;
  std::cout << "== " << res.hall << " x " << res.relic << ": frame " << res.frame << ", face " << res.face
            << ", " << 100 * res.reflected_fraction << "% of mirror rays meet a visitor, "
            << 100 * res.seen_through_fraction << "% of pixels see one through glass, "
            << res.foreground_points << " foreground points" << std::endl;
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

  const std::filesystem::path dir = std::filesystem::path(command.out) / "images";
  std::filesystem::create_directories(dir);
  display::writePngAtomically(dir / (res.hall + "_" + res.relic + ".png"), res.strip);
}

int evalTracer(const TracerEvalCommand& command) {
  const TracerEvalOptions& o = command.eval;
  // Each hall is also the built-in scene that brings its visitors.
  for (const std::string& hall : o.halls)
    if (hall != "room" && hall != "gallery" && hall != "atrium")
      throw InputError("command line", "--halls", "room, gallery or atrium", hall);
  const std::vector<std::string> relics = sim::builtinRelicNames();
  for (const std::string& relic : o.relics)
    if (std::find(relics.begin(), relics.end(), relic) == relics.end())
      throw InputError("command line", "--relics", "built-in relics (" + relics::relicNameList() + ")",
                       relic);
  std::vector<SceneResult> results;
  for (const std::string& hall : o.halls)
    for (const std::string& relic : o.relics) {
      results.push_back(evaluateTracerScene(hall, relic, o));
      reportScene(results.back(), command);
    }
  const std::string table = tracerMarkdownTable(results, o);
  std::ostringstream bars;
  const bool fg_ok = reportTracerBars(results, bars);
  std::cout << "\n" << table << "\n" << bars.str();
  writeTracerResults(results, o, command.out, table, bars.str());
  std::cout << "wrote " << command.out << "/{table.md,results.csv,results.json,plot.svg,images/}\n";
  if (command.require_fg_bars && !fg_ok) {
    std::cerr << "the fg_mse bars (ours <= ibl / 4 and < ssrt) do not hold\n";
    return 1;
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval tracer",
    [](CLI::App& sub) {
      auto command = std::make_shared<TracerEvalCommand>();
      TracerEvalOptions* o = &command->eval;
      sub.add_option("--halls", o->halls, "Halls (room, gallery, atrium)")
          ->capture_default_str()
          ->delimiter(',');
      sub.add_option("--relics", o->relics, "Relics (" + relics::relicNameList() + ")")
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
      sub.add_option("--out", command->out, "Output folder")->capture_default_str();
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
      sub.add_option("--visitor-model", o->visitor_model,
                     "Visitors instead of the halls' own: bodies (the default) or figures");
      addPanoramaAtInfinityFlag(sub, o->panorama_at_infinity);
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
      sub.add_flag("!--no-refracted-foreground", o->tracer.evaluation.refracted_foreground,
                   "Ours: glass refracts the IBL only, not the visitors seen through it");
      sub.add_flag("!--no-refraction", o->tracer.evaluation.refraction_enabled,
                   "Ours: glass shaded as opaque (no refraction pass: the opaque reference)");
      sub.add_option(
             "--refraction-depth", o->tracer.refraction_depth,
             "Ours, glass relics: interface events a transmitted path follows (0: measured on the relic)")
          ->capture_default_str()
          ->check(CLI::Range(0, 32));
      sub.add_option("--refraction-stride", o->tracer.refraction_stride,
                     "Ours, glass relics: pixels between the traced transmitted paths; the samples between "
                     "blend them (1: every sample traces)")
          ->capture_default_str()
          ->check(CLI::Range(1, 4));
      sub.add_option(
             "--refraction-branch-rays", o->tracer.refraction_branch_rays,
             "Ours, glass relics: rays a path may spend following the light reflected inside at an exit "
             "(0: summed as between parallel walls)")
          ->capture_default_str()
          ->check(CLI::Range(0, 64));
      sub.add_option(
             "--refraction-branch-weight", o->tracer.refraction_branch_weight,
             "Ours, glass relics: share of the entering light below which that light is summed, not followed")
          ->capture_default_str()
          ->check(CLI::Range(0.0f, 1.0f));
      sub.add_option(
             "--refraction-supersample", o->tracer.refraction_supersample_contrast,
             "Ours, glass relics: luminance ratio of the transmitted light within a pixel above which its "
             "samples take the mean of more paths (0: off)")
          ->capture_default_str();
      sub.add_option("--transmitted-lobe-scale", o->tracer.evaluation.transmitted_roughness_scale,
                     "Ours, glass relics: scales the transmitted lobe's derived roughness (checks)")
          ->capture_default_str()
          ->check(CLI::Range(0.0f, 4.0f));
      sub.add_option("--level-bias", o->tracer.evaluation.level_bias,
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
      sub.add_flag("!--no-rough-interleave", o->tracer.evaluation.rough_interreflection_interleaved,
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
      sub.add_flag("--no-interreflection", o->no_interreflection,
                   "Ours: no bounce where a mirror ray meets the relic itself (default: one bounce)");
      sub.add_option("--voxel-size", o->tracer.grid.voxel_size, "Ours: voxel size, metres")
          ->capture_default_str()
          ->check(CLI::Range(0.005f, 0.5f));
      sub.add_flag("--require-fg-bars", command->require_fg_bars,
                   "Exit 1 unless ours' fg_mse <= ibl's / 4 and < ssrt's on every scene");
      return [command] { return evalTracer(*command); };
    },
    "The nine-scene table: ours, IBL, SSRT and path tracing at equal time and equal quality"});

}  // namespace holo::app
