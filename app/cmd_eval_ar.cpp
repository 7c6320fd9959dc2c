// `holopyramid eval ar`: the AR composite against the path-traced truth on the simulated museum,
// delta path tracing against two-pass differential rendering at equal time (eval/ar_evaluation.hpp).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "command.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/ar_evaluation.hpp"
#include "holo/eval/scoring.hpp"

namespace holo::app {
namespace {

struct Options {
  eval::ArEvaluationOptions evaluation;
  std::string out;
};

void print(const char* name, const eval::ArErrors& e) {
  std::cout << name << ": RMSE (8-bit codes) relic and shadow " << e.region << ", relic " << e.relic
            << ", shadow " << e.shadow << ", image " << e.image;
}

int run(const Options& o) {
  const eval::ArEvaluation e = eval::evaluateArComposite(o.evaluation);
  std::cout << std::setprecision(4) << "scene: " << o.evaluation.scene << "  size: " << o.evaluation.width
            << "x" << o.evaluation.height << "  truth spp: " << o.evaluation.truth_spp << "\n"
            << "region pixels: " << e.region_pixels << " (relic " << e.relic_pixels << ", shadow and light "
            << e.shadow_pixels << ")\n";
  print("delta path tracing", e.delta.rmse);
  std::cout << "  spp " << e.delta.spp << " (relic pixels x" << o.evaluation.relic_spp_factor << ")  ms "
            << e.delta.ms << "  rays " << e.delta.rays << "  traced pixels " << e.traced_pixels << "\n";
  print("two-pass differential", e.two_pass.rmse);
  std::cout << "  spp " << e.two_pass.spp << "  ms " << e.two_pass.ms << "  rays " << e.two_pass.rays << "\n";
  print("two-pass differential, shared samples", e.two_pass_shared.rmse);
  std::cout << "  spp " << e.two_pass_shared.spp << "  ms " << e.two_pass_shared.ms << "  rays "
            << e.two_pass_shared.rays << "\n";
  print("delta path tracing, change filtered (the product's composite)", e.filtered.rmse);
  std::cout << "  ms " << e.filtered.ms << "\n";
  print("adversary without the relic's shadow and light", e.no_shadow);
  std::cout << "\n";
  print("delta path tracing with the real pixels exact (its relic pixels alone)", e.delta_relic_alone);
  std::cout << "\n";
  print("the exact local scene path traced at delta's spp (sampling noise alone)", e.exact_scene);
  std::cout << "\n";
  if (e.glass_opaque) {
    print("the composite with the relic's glass opaque", *e.glass_opaque);
    std::cout << "\n  glass / opaque error over the relic and shadow: "
              << (e.glass_opaque->region > 0 ? e.filtered.rmse.region / e.glass_opaque->region : 0.0) << "\n";
  }
  std::cout << "caustic photons traced: " << e.caustic_photons << "\n";
  if (e.without_light_tracer) {
    print("the composite without the caustic's light tracer (BSDF sampling alone)", *e.without_light_tracer);
    std::cout << "\n  over the caustic's pixels (" << e.caustic_pixels << "): with the light tracer "
              << e.caustic_rmse << ", without " << e.caustic_rmse_without_light_tracer << "\n"
              << "  mean luminance change over the shadow and light: truth " << e.shadow_change_truth
              << ", with the light tracer " << e.shadow_change << ", without "
              << e.shadow_change_without_light_tracer << "\n";
  }
  const auto ratios = [&](const char* name, const eval::ArMethodScore& two_pass) {
    const auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
    const double region = ratio(two_pass.rmse.region, e.delta.rmse.region);
    std::cout << name << " / delta error over the relic and shadow at equal CPU time: " << region
              << " (bar >= " << eval::kArDeltaOverTwoPass << ": "
              << (region >= eval::kArDeltaOverTwoPass ? "met" : "NOT met") << "); over the relic "
              << ratio(two_pass.rmse.relic, e.delta.rmse.relic) << ", the shadow "
              << ratio(two_pass.rmse.shadow, e.delta.rmse.shadow) << ", the image "
              << ratio(two_pass.rmse.image, e.delta.rmse.image) << "; at most "
              << ratio(two_pass.rmse.region, e.delta_relic_alone.region)
              << " over the relic and shadow with delta's real pixels exact\n";
  };
  std::cout << "\n";
  ratios("two-pass", e.two_pass);
  ratios("two-pass, shared samples", e.two_pass_shared);
  if (o.evaluation.relic_spp_factor > 1) {
    print("two-pass differential, relic pixels sampled as delta's", e.two_pass_split.rmse);
    std::cout << "  spp " << e.two_pass_split.spp << "  ms " << e.two_pass_split.ms << "\n";
    print("two-pass differential, shared samples, relic pixels sampled as delta's",
          e.two_pass_shared_split.rmse);
    std::cout << "  spp " << e.two_pass_shared_split.spp << "  ms " << e.two_pass_shared_split.ms << "\n";
    ratios("two-pass, relic pixels sampled as delta's", e.two_pass_split);
    ratios("two-pass, shared samples, relic pixels sampled as delta's", e.two_pass_shared_split);
  }
  if (!o.out.empty()) {
    std::filesystem::create_directories(o.out);
    eval::writeImagePair(o.out + "/truth.exr", e.truth, e.exposure);
    eval::writeImagePair(o.out + "/delta.exr", e.delta_composite, e.exposure);
    eval::writeImagePair(o.out + "/two_pass.exr", e.two_pass_composite, e.exposure);
    eval::writeImagePair(o.out + "/two_pass_shared.exr", e.two_pass_shared_composite, e.exposure);
    eval::writeImagePair(o.out + "/filtered.exr", e.filtered_composite, e.exposure);
    eval::writeImagePair(o.out + "/no_shadow.exr", e.no_shadow_composite, e.exposure);
    if (e.glass_opaque) {
      eval::writeImagePair(o.out + "/glass_opaque.exr", e.glass_opaque_composite, e.exposure);
      cv::Mat glass_strip;  // truth | the product's composite | the same with the glass opaque
      cv::hconcat(std::vector<cv::Mat>{e.truth, e.filtered_composite, e.glass_opaque_composite}, glass_strip);
      eval::writeImagePair(o.out + "/glass_strip.exr", glass_strip, e.exposure);
    }
    if (e.without_light_tracer) {
      cv::Mat caustic_strip;  // truth | the product's composite | without the caustic's light tracer
      cv::hconcat(std::vector<cv::Mat>{e.truth, e.filtered_composite, e.without_light_tracer_composite},
                  caustic_strip);
      eval::writeImagePair(o.out + "/caustic_strip.exr", caustic_strip, e.exposure);
    }
    cv::Mat strip;  // truth | the product's composite | two-pass | without the shadow
    cv::hconcat(
        std::vector<cv::Mat>{e.truth, e.filtered_composite, e.two_pass_composite, e.no_shadow_composite},
        strip);
    eval::writeImagePair(o.out + "/strip.exr", strip, e.exposure);
    std::cout << "images: " << o.out << "\n";
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval ar",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      auto& e = o->evaluation;
      sub.add_option("--scene", e.scene, "Simulated museum scene")->capture_default_str();
      sub.add_option("--relic", e.relic, "Built-in relic name or glTF file (default: the scene's)");
      sub.add_option("--width", e.width, "Check camera width")
          ->capture_default_str()
          ->check(CLI::Range(1, 4096));
      sub.add_option("--height", e.height, "Check camera height")
          ->capture_default_str()
          ->check(CLI::Range(1, 4096));
      sub.add_option("--truth-spp", e.truth_spp, "Truth samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--spp", e.method_spp, "Delta path tracing's samples per pixel (the time budget)")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 16));
      sub.add_option("--relic-spp-factor", e.relic_spp_factor,
                     "Delta path tracing's relic pixels take this many times --spp samples (the two-pass "
                     "renderers are measured both with every pixel alike and with this split)")
          ->capture_default_str()
          ->check(CLI::Range(1, 64));
      sub.add_option("--max-bounces", e.max_bounces, "Scatterings per path")
          ->capture_default_str()
          ->check(CLI::Range(1, 64));
      sub.add_flag(
          "--no-sensor-noise", [e = &e](std::int64_t n) { e->sensor_noise = n == 0; },
          "The camera's colour and depth without the sensor model's noise");
      sub.add_flag(
          "--traced-relic-reflections", [e = &e](std::int64_t n) { e->measured_real_radiance = n == 0; },
          "The relic's pixels path trace the local scene's model of the real surfaces it reflects, not "
          "the camera's radiance where the camera sees them");
      sub.add_option(
             "--delta-bounces", e.delta_bounces,
             "Delta path tracing: real-surface levels whose change is traced (1: the primary hit only)")
          ->capture_default_str()
          ->check(CLI::Range(1, 64));
      sub.add_option("--seed", e.seed, "Sampling seed")->capture_default_str();
      sub.add_option("--lamp", e.lamp_radiance,
                     "Add a small bright lamp (5 degrees in radius, this radiance) to the hall's panorama, "
                     "up behind the relic as the camera sees it: a glass relic focuses it into a caustic")
          ->check(CLI::Range(0.0f, 1e6f));
      sub.add_option("--out", o->out,
                     "Folder for truth, delta, two_pass, two_pass_shared, no_shadow, strip (EXR + PNG); a "
                     "transmissive relic also "
                     "glass_opaque and glass_strip");
      return [o] { return run(*o); };
    },
    "The AR composite against the path-traced truth; delta path tracing vs two-pass at equal time"});

}  // namespace holo::app
