// `holopyramid eval caustics`: a glass sphere over a diffuse plane under a small bright light,
// the photon map against a converged light tracer (eval/caustic_evaluation.hpp).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "command.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/caustic_evaluation.hpp"
#include "holo/eval/scoring.hpp"

namespace holo::app {
namespace {

struct Options {
  eval::CausticEvaluationOptions evaluation;
  std::string out;
};

const char* verdict(bool met) {
  return met ? "met" : "NOT met";
}

int run(const Options& o) {
  const eval::CausticEvaluation e = eval::evaluateCaustics(o.evaluation);
  const eval::CausticScene& s = o.evaluation.scene;
  std::cout << std::setprecision(4) << "scene: " << (o.evaluation.opaque ? "opaque" : "glass") << " sphere R "
            << s.radius << " m, IOR " << s.ior << ", centre " << s.centre_height
            << " m over the plane; point light " << s.light_power << " W at " << s.light_distance << " m, "
            << s.light_angle_deg << " deg from the vertical\n"
            << "caustic plan: " << (e.plan.runs ? "runs" : "off") << " (" << e.plan.reason << ")\n"
            << "photons traced " << e.photons_traced << ", stored " << e.photons_stored << "\n";
  if (!e.plan.runs) return 0;
  const double peak = e.peakErrorOverRadius(s.radius);
  const double axis = glm::length(e.reference_peak - e.axis_point) / s.radius;
  std::cout << "photon map: " << o.evaluation.photons << " photons, kernel "
            << o.evaluation.kernel_radius_over_radius
            << " R; light tracer: " << o.evaluation.reference_photons << " photons; receiver "
            << o.evaluation.resolution << "^2 cells\n"
            << "peak: photon map (" << e.peak.x << ", " << e.peak.y << ") m, light tracer ("
            << e.reference_peak.x << ", " << e.reference_peak.y << ") m, symmetry axis (" << e.axis_point.x
            << ", " << e.axis_point.y << ") m\n"
            << "peak error " << peak << " R (bar < " << eval::kCausticPeakOverRadius << ": "
            << verdict(peak < eval::kCausticPeakOverRadius) << "); light tracer from the axis " << axis
            << " R\n"
            << "power on the disc of R round the peak: photon map " << e.power << " W, light tracer "
            << e.reference_power << " W, error " << e.powerError() << " (bar < "
            << eval::kCausticPowerRelative << ": " << verdict(e.powerError() < eval::kCausticPowerRelative)
            << ")\n"
            << "irradiance at the peak (disc of 0.1 R): photon map " << e.peak_irradiance
            << " W/m^2, light tracer " << e.reference_peak_irradiance << " W/m^2, ratio "
            << e.peakIrradianceRatio() << "\n";
  if (o.evaluation.live_photons > 0) {
    const double live_peak = e.livePeakErrorOverRadius(s.radius);
    std::cout << "live light tracer (the pyramid views'): " << o.evaluation.live_photons << " photons, "
              << e.live_photons_stored << " landed, " << e.live_ms << " ms\n"
              << "live peak (" << e.live_peak.x << ", " << e.live_peak.y << ") m, error " << live_peak
              << " R (bar < " << eval::kCausticPeakOverRadius << ": "
              << verdict(live_peak < eval::kCausticPeakOverRadius) << ")\n"
              << "live power on the disc of R " << e.live_power << " W, error " << e.livePowerError()
              << " (bar < " << eval::kCausticPowerRelative << ": "
              << verdict(e.livePowerError() < eval::kCausticPowerRelative) << "); irradiance at the peak "
              << e.live_peak_irradiance << " W/m^2, ratio "
              << (e.reference_peak_irradiance > 0 ? e.live_peak_irradiance / e.reference_peak_irradiance
                                                  : 0.0)
              << "\n";
  }
  if (!o.out.empty()) {
    std::filesystem::create_directories(o.out);
    // photon map | light tracer | the opaque sphere (its shadow, no caustic), direct light added
    const cv::Mat glass_pm = eval::receiverIrradiance(s, false, e.photon_map);
    const cv::Mat glass_lt = eval::receiverIrradiance(s, false, e.light_tracer);
    const cv::Mat opaque =
        eval::receiverIrradiance(s, true,
                                 {e.photon_map.receiver, e.photon_map.resolution,
                                  cv::Mat::zeros(e.photon_map.irradiance.size(), CV_32FC3)});
    cv::Mat strip;
    cv::hconcat(std::vector<cv::Mat>{glass_pm, glass_lt, opaque}, strip);
    const float exposure = float(0.25 / std::max(1e-6, cv::mean(opaque)[1]));
    eval::writeImagePair(o.out + "/caustics.exr", strip, exposure);
    std::cout << "images: " << o.out << "/caustics.{exr,png}\n";
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval caustics",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      auto& e = o->evaluation;
      sub.add_option("--photons", e.photons, "Photons of the photon map")
          ->capture_default_str()
          ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 31));
      sub.add_option("--reference-photons", e.reference_photons, "Photons of the light tracer")
          ->capture_default_str()
          ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 32));
      sub.add_option("--resolution", e.resolution, "Receiver cells along a side")
          ->capture_default_str()
          ->check(CLI::Range(8, 4096));
      sub.add_option("--kernel", e.kernel_radius_over_radius, "Photon map kernel radius, in sphere radii")
          ->capture_default_str()
          ->check(CLI::Range(1e-4f, 1.0f));
      sub.add_option("--live-photons", e.live_photons,
                     "Photons of the live light tracer (reflect/caustic_tracer.hpp); 0: not run")
          ->capture_default_str();
      sub.add_flag("--opaque", e.opaque, "An opaque (mirror metal) sphere instead of glass");
      sub.add_option("--seed", e.seed, "Sampling seed")->capture_default_str();
      sub.add_option("--out", o->out, "Folder for caustics.exr and caustics.png");
      return [o] { return run(*o); };
    },
    "Caustics of a glass sphere: the photon map against a converged light tracer"});

}  // namespace holo::app
