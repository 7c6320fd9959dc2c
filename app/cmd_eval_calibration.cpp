// `holopyramid eval calibration --recording DIR`: calibrates a recording of the simulated museum
// (`simulate --calibration`) and measures the result against the recording's truth and, through
// the live loop, on the displayed images (eval/calibration_evaluation.hpp). Writes
// calibration_eval.json and calibration_eval.png into --out; exit code 0 when every figure is
// within its bar, 3 when one is not (or the calibration failed), 2 on bad input.
#include <fmt/format.h>

#include <iostream>

#include "command.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/calibration_evaluation.hpp"

namespace holo::app {
namespace {

struct Options {
  eval::CalibrationEvalOptions eval;
  std::string recording;
  std::string out = "out/eval_calibration";
  bool quiet = false;
};

int run(Options o) {
  o.eval.recording = o.recording;
  o.eval.out = o.out;
  o.eval.quiet = o.quiet;
  const eval::CalibrationEvaluation e = eval::evaluateCalibration(o.eval, std::cout);
  if (!e.calibration_passed) {
    std::cout << "the calibration failed (see its steps above); nothing to compare\n";
    return 3;
  }
  bool pass = true;
  const auto row = [&](const char* figure, double value, double bar, const char* unit, bool below = true) {
    const bool ok = below ? value < bar : value > bar;
    pass = pass && ok;
    std::cout << fmt::format("  {:<58} {:>9.3f} {:<6} ({} {:.3g}) {}\n", figure, value, unit,
                             below ? "<" : ">", bar, ok ? "PASS" : "FAIL");
  };
  std::cout << fmt::format(
      "calibration of {} cameras against the truth (worst camera), {} loop frames at {} px:\n",
      e.cameras.size(), e.frames, e.view_size);
  row("intrinsics (fx, fy, cx, cy)", e.worst.intrinsics_error_pct, eval::kMaxIntrinsicsErrorPct, "%");
  row("camera position", e.worst.position_error_mm, eval::kMaxPositionErrorMm, "mm");
  row("camera rotation", e.worst.rotation_error_deg, eval::kMaxRotationErrorDeg, "deg");
  row("depth scale", e.worst.depth_scale_error_pct, eval::kMaxDepthScaleErrorPct, "%");
  row("colour gains", e.worst.gain_error_pct, eval::kMaxGainErrorPct, "%");
  const eval::DisplayedError& fitted = e.displayed.at(0);
  const eval::DisplayedError& without = e.displayed.at(1);
  row("displayed error, fitted calibration", fitted.mean_codes, eval::kMaxDisplayedErrorCodes, "codes");
  row("displayed error, without registration and colour matching", without.mean_codes, fitted.mean_codes,
      "codes", false);
  std::cout << fmt::format("  on the relic's pixels: fitted {:.3f}, without {:.3f} codes\n",
                           fitted.relic_codes, without.relic_codes);
  std::cout << "wrote " << (o.eval.out / "calibration_eval.json").string() << " and calibration_eval.png\n";
  return pass ? 0 : 3;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval calibration",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.add_option("--recording", o->recording, "A recording made by `holopyramid simulate --calibration`")
          ->required();
      sub.add_option("--out", o->out, "Output folder (calibration/, JSON, PNG)")->capture_default_str();
      sub.add_option("--frames", o->eval.frames, "Visitor frames run through the loop")
          ->capture_default_str();
      sub.add_option("--view-size", o->eval.view_size, "Face view pixels (square)")->capture_default_str();
      sub.add_option("--background-frames", o->eval.background_frames,
                     "The recording's frames of the empty hall (simulate --background-frames)")
          ->capture_default_str();
      sub.add_flag("-q,--quiet", o->quiet, "No progress output");
      return [o] { return run(*o); };
    },
    "Calibrate a simulated recording and measure it: figures against the truth, displayed error of the "
    "loop against the true calibration"});

}  // namespace holo::app
