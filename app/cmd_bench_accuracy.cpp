// `holopyramid bench accuracy`: accuracy against time on one scene (eval/accuracy_sweep.hpp): each
// reflection method's quality knobs swept and scored against the path-traced truth; writes
// accuracy.csv and accuracy.svg (fg_mse against milliseconds per view, the Pareto front marked);
// with --effects, each effect of the plan switched against the default tracer on each scene of
// --scenes: effects.csv, effects.svg and effects.md.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "holo/core/files.hpp"
#include "holo/eval/accuracy_sweep.hpp"
#include "holo/relics/relics.hpp"

namespace holo::app {

using namespace holo::eval;
namespace {

struct AccuracyCommand {
  AccuracyOptions sweep;
  std::string out = "bench-accuracy";
  bool effects = false;
  std::vector<std::string> scenes;  // hall:relic; empty: effectScenes()
};

std::string fmt(double v, int precision) {
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

// Each scene's effect points (sweepAccuracy with effects_only), one table, CSV and plot for all.
int benchEffects(const AccuracyCommand& command) {
  const std::vector<std::string> scenes = command.scenes.empty() ? effectScenes() : command.scenes;
  std::vector<SceneSweep> sweeps;
  std::string csv;
  for (const std::string& scene : scenes) {
    const auto colon = scene.find(':');
    AccuracyOptions o = command.sweep;
    o.effects_only = true;
    o.hall = scene.substr(0, colon);
    o.relic = scene.substr(colon + 1);
    std::cout << "scene " << o.hall << " x " << o.relic << std::endl;
    SceneSweep s{o, sweepAccuracy(o)};
    const std::string rows = accuracyCsv(o, s.sweep);
    csv += csv.empty() ? rows : rows.substr(rows.find('\n') + 1);
    sweeps.push_back(std::move(s));
  }
  const std::filesystem::path dir = command.out;
  std::filesystem::create_directories(dir);
  const std::string table = effectsTable(sweeps);
  writeFileAtomically(dir / "effects.csv", csv);
  writeFileAtomically(dir / "effects.md", table);
  writeFileAtomically(
      dir / "effects.svg",
      effectsSvg(sweeps, "each effect against the default tracer, " + std::to_string(command.sweep.size) +
                             "^2, truth " + std::to_string(command.sweep.gt_spp) + " spp"));
  std::cout << table << "wrote " << (dir / "effects.csv").string() << ", effects.md and effects.svg\n";
  return 0;
}

int benchAccuracy(const AccuracyCommand& command) {
  if (command.effects) return benchEffects(command);
  const AccuracyOptions& o = command.sweep;
  const AccuracySweep sweep = sweepAccuracy(o);
  const std::vector<AccuracyPoint>& points = sweep.points;
  std::cout << o.hall << " x " << o.relic << ": frame " << sweep.frame << ", face " << sweep.face
            << std::endl;
  if (sweep.region_pixels == 0)
    std::cout << "no foreground region at the paper's threshold (0.2): fg_mse is 0 for every method\n";

  const std::filesystem::path dir = command.out;
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir / "accuracy.csv", accuracyCsv(o, sweep));
  writeFileAtomically(dir / "accuracy.svg",
                      accuracySvg(points, "fg_mse vs time per view: " + o.hall + " x " + o.relic + ", " +
                                              std::to_string(o.size) + "^2, " +
                                              std::to_string(sweep.region_pixels) + " foreground px"));
  for (const AccuracyPoint& p : points)
    std::cout << (p.pareto ? "* " : "  ") << std::left << std::setw(6) << p.method << std::setw(46) << p.knob
              << std::right << std::setw(10) << fmt(p.ms, 4) << " ms  fg_mse " << fmt(p.fg_mse, 4)
              << std::endl;
  std::cout << "wrote " << (dir / "accuracy.csv").string() << " and accuracy.svg (* = Pareto front)\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "bench accuracy",
    [](CLI::App& sub) {
      auto command = std::make_shared<AccuracyCommand>();
      AccuracyOptions* o = &command->sweep;
      sub.add_option("--hall", o->hall, "Hall (room, gallery, atrium): its walkers come along")
          ->capture_default_str()
          ->check(CLI::IsMember({"room", "gallery", "atrium", "window"}));
      sub.add_option("--relic", o->relic, "Relic (" + relics::relicNameList() + ")")
          ->capture_default_str()
          ->check(CLI::IsMember(relics::relicNames()));
      sub.add_option("--size", o->size, "View width and height, pixels")
          ->capture_default_str()
          ->check(CLI::Range(8, 1024));
      sub.add_option("--gt-spp", o->gt_spp, "Ground-truth samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--max-spp", o->max_spp, "Largest path-tracing spp of the sweep")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 16));
      sub.add_option("--repeats", o->repeats, "Runs per timing (the median is reported)")
          ->capture_default_str()
          ->check(CLI::Range(1, 100));
      sub.add_option("--close-visitors", o->close_visitors, "Visitors standing close to the pyramid")
          ->capture_default_str()
          ->check(CLI::Range(0, 4));
      sub.add_option("--visitor-model", o->visitor_model,
                     "Visitors instead of the hall's own: bodies (the default) or figures");
      addPanoramaAtInfinityFlag(sub, o->panorama_at_infinity);
      sub.add_flag("--effects", command->effects,
                   "Only the default tracer with each effect of the plan switched, on each of --scenes: "
                   "effects.csv, effects.md and effects.svg");
      sub.add_option(
             "--scenes", command->scenes,
             "With --effects: hall:relic scenes (default: the nine, gallery:bowl, gallery:metal-bowl, "
             "window:bowl)")
          ->delimiter(',')
          ->check([](const std::string& scene) -> std::string {
            const auto colon = scene.find(':');
            if (colon == std::string::npos) return "expected hall:relic, got " + scene;
            const std::string hall = scene.substr(0, colon), relic = scene.substr(colon + 1);
            for (const char* h : {"room", "gallery", "atrium", "window"})
              if (hall == h) {
                for (const std::string& r : relics::relicNames())
                  if (relic == r) return "";
                return "unknown relic " + relic + " (one of " + relics::relicNameList() + ")";
              }
            return "unknown hall " + hall + " (one of room, gallery, atrium, window)";
          });
      sub.add_option("--out", command->out, "Output folder")->capture_default_str();
      sub.add_option("--cache", o->cache, "Ground-truth cache folder")->capture_default_str();
      return [command] { return benchAccuracy(*command); };
    },
    "Accuracy against time: each method's quality knobs swept, CSV and the fg_mse/ms plot with its Pareto "
    "front"});

}  // namespace holo::app
