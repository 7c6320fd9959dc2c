// `holopyramid eval tracer`: the nine-scene evaluation (the paper's Table 1 extended with the
// baselines, eval/tracer_evaluation.hpp) over --halls x --relics; prints each scene's methods as
// it finishes, then the bars, a Markdown table, and writes CSV, JSON, an SVG plot (fg_mse against
// time) and, per scene, a strip of the images (gt | ours | ibl | ssrt | mcpt_equal_time |
// mcpt_equal_quality | the foreground region).
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/eval/tracer_evaluation.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/relics.hpp"

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

std::string fmt(double v, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// A glass relic's bar on fg_mse (where visitors are seen through and in it): a quarter of the same
// renderer's with the refraction reading the IBL only, or 1.1x the reconstruction's floor where
// that quarter is below what any renderer of the reconstruction can reach.
double glassForegroundBar(const SceneResult& r) {
  return std::max(r.at("ours_ibl_refraction").fg_mse / 4.0, 1.1 * std::max(0.0, r.reconstruction_floor));
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
  if (std::any_of(results.begin(), results.end(),
                  [](const SceneResult& r) { return r.has("ours_glass_opaque"); })) {
    s << "\nGlass relics, x 1e-2: mse over the view (the pixels off the relic are the same black in every "
         "method, so its ratios are those over the relic's pixels); ours_glass_opaque: ours with the glass "
         "shaded as opaque; ours_ibl_refraction: ours refracting the IBL only. Times per view at frame time, "
         "ms.\n\n"
      << "| scene | seen through | ours mse | opaque mse | opaque/ours | ours fg_mse | ibl-refraction fg_mse "
         "| "
         "recon floor | fg bar | ours ms | opaque ms | ibl-refraction ms |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const SceneResult& r : results) {
      if (!r.has("ours_glass_opaque")) continue;
      const Entry &ours = r.at("ours"), &opaque = r.at("ours_glass_opaque");
      const bool ibl_only = r.has("ours_ibl_refraction");
      s << "| " << r.hall << " x " << r.relic << " | " << fmt(100 * r.seen_through_fraction, 1) << "% | "
        << fmt(100 * ours.mse, 3) << " | " << fmt(100 * opaque.mse, 3) << " | "
        << (ours.mse > 0 ? fmt(opaque.mse / ours.mse, 1) : std::string("-")) << " | "
        << (r.fg_pixels > 0 ? fmt(100 * ours.fg_mse, 3) : std::string("-")) << " | "
        << (ibl_only && r.fg_pixels > 0 ? fmt(100 * r.at("ours_ibl_refraction").fg_mse, 3) : std::string("-"))
        << " | " << (r.reconstruction_floor >= 0 ? fmt(100 * r.reconstruction_floor, 3) : "-") << " | "
        << (ibl_only && r.fg_pixels > 0 ? fmt(100 * glassForegroundBar(r), 3) : std::string("-")) << " | "
        << fmt(ours.ms, 2) << " | " << fmt(opaque.ms, 2) << " | "
        << (ibl_only ? fmt(r.at("ours_ibl_refraction").ms, 2) : std::string("-")) << " |\n";
    }
    s << "\nfg bar: max(ibl-refraction fg_mse / 4, 1.1 x recon floor), what ours' fg_mse must stay within.\n";
  }
  return s.str();
}

// The evaluation's bars, one line each with the worst scene; returns whether the fg_mse bars against
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
      time_ibl{"ours per view <= 1.1x the paper ibl's per view, frame work amortised (ratio >= 0.91)"},
      glass_opaque{"glass: ours mse <= 1/4 of the glass shaded as opaque (opaque/ours >= 4)"},
      glass_fg{"glass: ours fg_mse <= max(ibl-refraction's / 4, 1.1x recon floor) (bar/ours >= 1)"};
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
    if (r.has("ours_glass_opaque") && ours.mse > 0)
      check(glass_opaque, r.at("ours_glass_opaque").mse / ours.mse, 4.0, where);
    if (r.has("ours_ibl_refraction") && r.fg_pixels > 0 && ours.fg_mse > 0)
      check(glass_fg, glassForegroundBar(r) / ours.fg_mse, 1.0, where);
    check(time_view, r.at("ibl_same_aa").view_ms / ours.view_ms, 1.0 / 1.1, where);
    check(time_ibl, r.at("ibl").ms / ours.ms, 1.0 / 1.1, where);
  }
  // The fg_mse bars hold on "every one of the scenes": a scene without a foreground region (the
  // visitors change no displayed pixel by the threshold) cannot show them, so it fails them.
  const int glass_scenes = static_cast<int>(std::count_if(
      results.begin(), results.end(), [](const SceneResult& r) { return r.has("ours_glass_opaque"); }));
  for (const Bar* b : {&ibl, &ssrt, &eq, &et, &time_view, &time_ibl, &glass_opaque, &glass_fg}) {
    const bool glass_bar = b == &glass_opaque || b == &glass_fg;
    if (glass_bar && glass_scenes == 0) continue;
    const int of = glass_bar ? glass_scenes : static_cast<int>(results.size());
    const bool all = b->scenes == of;
    out << (b->ok && all ? "MET     " : "NOT MET ") << b->what << ": worst " << fmt(b->worst, 2) << " ("
        << b->where << ")";
    if (!all)
      out << "; " << (b->ok ? "holds on" : "measured on") << " the " << b->scenes << " of " << of
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

void writeOutputs(const std::vector<SceneResult>& results, const TracerEvalCommand& command,
                  const std::string& table, const std::string& bars) {
  const TracerEvalOptions& o = command.eval;
  const std::filesystem::path dir = command.out;
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
                         {"seen_through_fraction", r.seen_through_fraction},
                         {"mcpt_build_ms", r.mcpt_build_ms},
                         {"size", o.size},
                         {"close_visitors", o.close_visitors},
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

int evalTracer(const TracerEvalCommand& command) {
  const TracerEvalOptions& o = command.eval;
  // Each hall is also the built-in scene that brings its visitors.
  for (const std::string& hall : o.halls)
    if (hall != "room" && hall != "gallery" && hall != "atrium")
      throw InputError("command line", "--halls", "room, gallery or atrium", hall);
  const std::vector<std::string> relics = sim::builtinRelicNames();
  for (const std::string& relic : o.relics)
    if (std::find(relics.begin(), relics.end(), relic) == relics.end())
      throw InputError("command line", "--relics", "built-in relics (" + sim::relicNameList() + ")", relic);
  std::vector<SceneResult> results;
  for (const std::string& hall : o.halls)
    for (const std::string& relic : o.relics) {
      results.push_back(evaluateTracerScene(hall, relic, o));
      reportScene(results.back(), command);
    }
  const std::string table = markdownTable(results, o);
  std::ostringstream bars;
  const bool fg_ok = reportBars(results, bars);
  std::cout << "\n" << table << "\n" << bars.str();
  writeOutputs(results, command, table, bars.str());
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
      sub.add_option("--relics", o->relics, "Relics (" + sim::relicNameList() + ")")
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
                   "Ours: glass shaded as opaque (the renderer before the refraction pass)");
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
      sub.add_flag(
          "--no-interreflection", o->no_interreflection,
          "Ours: no bounce where a mirror ray meets the relic itself (the before of docs/tracer.md)");
      sub.add_option("--voxel-size", o->tracer.grid.voxel_size, "Ours: voxel size, metres")
          ->capture_default_str()
          ->check(CLI::Range(0.005f, 0.5f));
      sub.add_flag("--require-fg-bars", command->require_fg_bars,
                   "Exit 1 unless ours' fg_mse <= ibl's / 4 and < ssrt's on every scene");
      return [command] { return evalTracer(*command); };
    },
    "The nine-scene table: ours, IBL, SSRT and path tracing at equal time and equal quality"});

}  // namespace holo::app
