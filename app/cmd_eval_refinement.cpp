// `holopyramid eval refinement`: a still scene's error against the converged image frame after
// frame with progressive refinement, at the live view size (eval/refinement_evaluation.hpp).
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "command.hpp"
#include "holo/core/files.hpp"
#include "holo/eval/refinement_evaluation.hpp"

namespace holo::app {
namespace {

struct Options {
  eval::RefinementEvaluationOptions evaluation;
  std::string out;
};

int run(const Options& o) {
  const eval::RefinementEvaluation e = eval::evaluateRefinement(o.evaluation);
  const int two_seconds = e.framesWithin(2.0);
  const int below = e.firstFrameBelow(0.10);
  std::cout << std::setprecision(4) << "relic " << o.evaluation.relic << ", "
            << (o.evaluation.panorama.empty() ? std::string("synthetic sky") : o.evaluation.panorama)
            << ", four views of " << o.evaluation.view_size << "^2 at the default eyes, "
            << (o.evaluation.live_loop ? "the live loop's settings with the interreflection on"
                                       : "the tracer's defaults")
            << "\n"
            << "plan: " << e.plan << "\n"
            << "region: " << e.region_pixels << " px where the interreflection shows, its light's rms "
            << e.interreflected_rms << "; converged: " << o.evaluation.converged_sets << " sets\n"
            << "frame ms: refining " << e.refining_ms << " (" << 1000.0 / std::max(e.refining_ms, 1e-9)
            << " fps), eyes moving " << e.moved_ms << ", still without refinement " << e.reused_ms << "\n"
            << "frame error (against the converged image / interreflected light)\n";
  for (std::size_t n = 0; n < e.error.size(); ++n)
    std::cout << std::setw(6) << n + 1 << std::setw(12) << e.error[n] << std::setw(10) << e.frame_ms[n]
              << "\n";
  const int shown = std::min(two_seconds, int(e.error.size()));
  std::cout << "2 s at the refining rate: " << two_seconds << " frames; error at frame " << shown << ": "
            << (shown >= 1 ? e.error[std::size_t(shown) - 1] : -1.0) << "; first frame <= 10%: " << below
            << "; monotonic over frames 1.." << e.error.size() << ": "
            << (e.monotonicUpTo(int(e.error.size())) ? "yes" : "no") << "\n";
  if (!o.out.empty()) {
    std::filesystem::create_directories(o.out);
    std::string csv = "frame,error,frame_ms\n";
    for (std::size_t n = 0; n < e.error.size(); ++n)
      csv += std::to_string(n + 1) + "," + std::to_string(e.error[n]) + "," + std::to_string(e.frame_ms[n]) +
             "\n";
    writeFileAtomically(o.out + "/refinement.csv", csv);
    writeFileAtomically(
        o.out + "/refinement.svg",
        eval::refinementPlotSvg(e, "Progressive refinement, " + o.evaluation.relic + ", " +
                                       std::to_string(o.evaluation.view_size) + "^2 x 4 views"));
    std::cout << "curve: " << o.out << "/refinement.{csv,svg}\n";
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval refinement",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      auto& e = o->evaluation;
      sub.add_option("--relic", e.relic, "Built-in relic")->capture_default_str();
      sub.add_option("--panorama", e.panorama,
                     "HDR panorama (default: a synthetic sky with a bright window)");
      sub.add_option("--view-size", e.view_size, "Pixels per face view")
          ->capture_default_str()
          ->check(CLI::Range(8, 2048));
      sub.add_option("--frames", e.frames, "Frames of the curve")
          ->capture_default_str()
          ->check(CLI::Range(2, 4096));
      sub.add_option("--converged-sets", e.converged_sets, "Sample sets of the converged image")
          ->capture_default_str()
          ->check(CLI::Range(2, 4096));
      sub.add_option("--timing-frames", e.timing_frames, "Frames per median of the budget's frames")
          ->capture_default_str()
          ->check(CLI::Range(1, 1000));
      sub.add_flag("--live-loop", e.live_loop,
                   "The live loop's tracer settings (one sample per pixel, edge anti-aliasing) with the "
                   "interreflection on");
      sub.add_flag("!--no-axis-aligned-filter", e.axis_aligned_filter,
                   "Leave the rough lobe's axis-aligned filter off: the accumulation alone");
      sub.add_option("--out", o->out, "Folder for refinement.csv and refinement.svg");
      return [o] { return run(*o); };
    },
    "Progressive refinement: a still scene's error against the converged image, frame by frame"});

}  // namespace holo::app
