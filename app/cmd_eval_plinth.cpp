// `holopyramid eval plinth`: a glass relic on a virtual plinth under a small bright lamp, one
// pyramid view, ours against the path-traced truth over the plinth (eval/plinth_evaluation.hpp).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "command.hpp"
#include "holo/eval/plinth_evaluation.hpp"
#include "holo/eval/scoring.hpp"

namespace holo::app {
namespace {

struct Options {
  eval::PlinthEvaluationOptions evaluation;
  std::string out;
};

int run(const Options& o) {
  const eval::PlinthEvaluation e = eval::evaluatePlinth(o.evaluation);
  const auto& s = o.evaluation;
  std::cout << std::setprecision(4) << "scene: " << s.relic << " on a plinth; lamp " << s.lamp_radius_deg
            << " deg radius at " << s.lamp_angle_deg << " deg from the vertical, radiance " << s.lamp_radiance
            << ", sky " << s.sky_radiance << "\n"
            << "view: " << s.size << "^2; truth: gt, " << s.truth_spp << " spp\n"
            << "ours: " << e.ours_ms << " ms (first frame, plinth relit), caustic " << e.caustic_ms
            << " ms; photons traced " << e.photons_traced << ", landed " << e.photons_stored << "\n"
            << "plinth pixels " << e.plinth_pixels << ", relative RMSE (luminance) against the truth:\n"
            << "  ours " << e.error << "\n"
            << "  ours, caustic off " << e.error_no_caustic << "\n"
            << "  ours, no shadow nor caustic " << e.error_unshadowed << "\n"
            << "caustic pixels (truth > 1.1 x unshadowed) " << e.caustic_pixels << ": ours "
            << e.caustic_error << ", caustic off " << e.caustic_error_no_caustic << "\n";
  if (!o.out.empty()) {
    std::filesystem::create_directories(o.out);
    cv::Mat strip;
    cv::hconcat(std::vector<cv::Mat>{e.truth, e.ours, e.ours_no_caustic}, strip);
    const cv::Scalar mean = cv::mean(e.truth, e.plinth_mask);
    const float exposure = float(0.35 / std::max(1e-6, mean[1]));
    eval::writeImagePair(o.out + "/plinth.exr", strip, exposure);
    std::cout << "images: " << o.out << "/plinth.{exr,png} (truth | ours | ours, caustic off)\n";
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval plinth",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      auto& e = o->evaluation;
      sub.add_option("--relic", e.relic, "glass-sphere, or a built-in relic (glass-vase, crystal, ...)")
          ->capture_default_str();
      sub.add_option("--size", e.size, "View width and height, pixels")
          ->capture_default_str()
          ->check(CLI::Range(8, 2048));
      sub.add_option("--truth-spp", e.truth_spp, "Path-traced truth: samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--caustic-photons", e.caustic_photons, "Photons of the live caustic")
          ->capture_default_str()
          ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 31));
      sub.add_option("--seed", e.seed, "Truth's sampling seed")->capture_default_str();
      sub.add_option("--out", o->out, "Folder for plinth.exr and plinth.png");
      return [o] { return run(*o); };
    },
    "A glass relic on a plinth: ours (shadow and live caustic) against the path-traced truth"});

}  // namespace holo::app
