#include "holo/eval/tracer_report.hpp"

#include <algorithm>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "holo/core/files.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/loglog_plot.hpp"

namespace holo::eval {
namespace {

std::string fmt(double v, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// A glass relic's bar on fg_mse (where visitors are seen through and in it): a quarter of the same
// renderer's with the refraction reading the IBL only, or the margin over the reconstruction's
// floor where that quarter is below what any renderer of the reconstruction can reach.
double glassForegroundBar(const SceneResult& r) {
  return foregroundBarWithFloor(r.at("ours_ibl_refraction").fg_mse, r.reconstruction_floor);
}

}  // namespace

// fg_mse x 1e-2 as the paper's Table 1 with the ratios, then the times, then the glass relics.
std::string tracerMarkdownTable(const std::vector<SceneResult>& results, const TracerEvalOptions& o) {
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

bool reportTracerBars(const std::vector<SceneResult>& results, std::ostream& out) {
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
    if (!meetsRatioBar(value, bar)) b.ok = false;
  };
  for (const SceneResult& r : results) {
    const std::string where = r.hall + " x " + r.relic;
    const Entry& ours = r.at("ours");
    const Entry& eqe = r.at("mcpt_equal_quality");
    if (r.fg_pixels > 0 && ours.fg_mse > 0) {
      check(ibl, r.at("ibl").fg_mse / ours.fg_mse, kForegroundBelowReference, where);
      check(ssrt, r.at("ssrt").fg_mse / ours.fg_mse, kSsrtOverOurs, where);
      check(et, r.at("mcpt_equal_time").fg_mse / ours.fg_mse, kEqualTimeMcptOverOurs, where);
      check(eq, eqe.ms / ours.ms, kEqualQualityMcptTimeOverOurs,
            where + (eqe.reached ? "" : " (quality not reached)"));
    }
    if (r.has("ours_glass_opaque") && ours.mse > 0)
      check(glass_opaque, r.at("ours_glass_opaque").mse / ours.mse, kGlassOpaqueOverOurs, where);
    if (r.has("ours_ibl_refraction") && r.fg_pixels > 0 && ours.fg_mse > 0)
      check(glass_fg, glassForegroundBar(r) / ours.fg_mse, kForegroundBarOverOurs, where);
    check(time_view, r.at("ibl_same_aa").view_ms / ours.view_ms, kSameAaViewTimeOverOurs, where);
    check(time_ibl, r.at("ibl").ms / ours.ms, kIblTimeOverOurs, where);
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
    if (r.fg_pixels > 0 && r.reconstruction_floor >= 0 &&
        r.at("ibl").fg_mse / kForegroundBelowReference < r.reconstruction_floor)
      below += (below.empty() ? "" : ", ") + r.hall + " x " + r.relic +
               " (ibl / 4 = " + fmt(100 * r.at("ibl").fg_mse / kForegroundBelowReference, 3) + ", floor " +
               fmt(100 * r.reconstruction_floor, 3) + ")";
  if (!below.empty())
    out << "        ibl / 4 is below the reconstruction floor (x 1e-2) on: " << below << "\n";
  return ibl.ok && ssrt.ok;
}

void writeTracerResults(const std::vector<SceneResult>& results, const TracerEvalOptions& o,
                        const std::filesystem::path& dir, const std::string& table, const std::string& bars) {
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

}  // namespace holo::eval
