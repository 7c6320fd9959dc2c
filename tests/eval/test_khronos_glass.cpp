// The live renderer held to the path tracer on every Khronos model of ../shared/data (glass with
// textures, something opaque inside the glass, roughness and IOR grids, attenuation, a clearcoat),
// over the relic's pixels, as the pyramid displays them (Reinhard at the truth's exposure, sRGB
// codes 0-255, the mean over the channels of the absolute difference).
//
// CI size: a 40^2 view under one real panorama against a 64-spp truth (a few seconds per model),
// each model held to what the live renderer measures there with a margin (the truth's own noise
// counts: a second 64-spp truth is 4-7 codes from the first, 8.6 on the candle's pixels), below
// what it measured with the glass's textures read at the entry only (docs/materials.md).
// HOLO_FULL_EVAL=1: the 256^2 figure of docs/materials.md, under two real panoramas against a
// 256-spp truth, the bar of 8 codes (not met on the candle holder, 8.66 / 8.92; against
// 1024-spp truths 8.43 / 7.89: docs/materials.md says why).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "holo/core/ray_scene.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/eval/scoring.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "shared_data.hpp"

namespace holo::eval {
namespace {

bool fullEvaluation() {
  const char* env = std::getenv("HOLO_FULL_EVAL");
  return env != nullptr && std::string(env) == "1";
}

struct Size {
  int pixels, gt_spp;
  std::vector<std::string> panoramas;
};

Size evaluationSize() {
  if (fullEvaluation()) return {256, 256, {"hdri/rooitou_park_1k.hdr", "hdri/st_fagans_interior_1k.hdr"}};
  return {40, 64, {"hdri/rooitou_park_1k.hdr"}};
}

ReflectionScene khronosScene(const std::string& model, const std::string& panorama) {
  SceneOptions options;
  options.scene = "empty";
  options.relic = test::sharedData("models/" + model).string();
  options.panorama = test::sharedData(panorama).string();
  options.fit = true;
  return loadReflectionScene(options);
}

cv::Mat renderView(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
                   int spp, bool sun_light = true) {
  MethodSettings settings;
  settings.spp = spp;
  settings.with_visitors = false;
  settings.tracer.evaluation.sun_light = sun_light;
  return renderMethod(method, scene, camera, settings).image;
}

// The relic's pixels: 255 where the pixel centre's ray meets `relic` (its cut-out and invisible
// parts passed); `glass` gets those whose first hit is on a transmissive material.
cv::Mat relicPixels(const Model& relic, const CameraModel& camera, cv::Mat* glass = nullptr) {
  const reflect::RenderScene scene(relic, {});
  cv::Mat mask(camera.height(), camera.width(), CV_8UC1, cv::Scalar(0));
  if (glass) *glass = mask.clone();
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x) {
      const RayHit hit = scene.relicOnly().intersect(reflect::primaryRay(camera, vec2(float(x), float(y))));
      if (!hit.hit()) continue;
      mask.at<std::uint8_t>(y, x) = 255;
      if (glass && scene.relicGltfMaterial(hit, scene.relicOnly()).transmissive())
        glass->at<std::uint8_t>(y, x) = 255;
    }
  return mask;
}

// Mean absolute difference in sRGB codes over the mask's pixels, both images displayed at the
// truth's automatic exposure.
double meanCodes(const cv::Mat& ours_hdr, const cv::Mat& truth_hdr, const cv::Mat& mask) {
  const float exposure = reflect::autoExposure(truth_hdr);
  const cv::Mat a = reflect::toneMap(ours_hdr, exposure), b = reflect::toneMap(truth_hdr, exposure);
  double sum = 0;
  int n = 0;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<std::uint8_t>(y, x)) continue;
      for (int c = 0; c < 3; ++c)
        sum += std::abs(double(a.at<cv::Vec3b>(y, x)[c]) - double(b.at<cv::Vec3b>(y, x)[c]));
      ++n;
    }
  return n > 0 ? sum / (3.0 * n) : 0.0;
}

struct KhronosCase {
  std::string model;
  double ci_bar;  // sRGB codes at CI size (measured 11.7, 9.0, 3.9, 6.6; with the textures read at
                  // the entry only 32.5, 34.1, 5.7, 11.9)
  // The park's sun lights this model's diffuse surfaces: with the sun light switched off (the sun
  // in the 9 coefficients) it must be at least this many times further from the truth (measured
  // at CI size: the wicker 11.9 against 6.6, 1.8x; the candle holder, its candle lit through the
  // glass, 13.9 against 11.7, 1.2x; the grid's floor, whose shadow it was, now has the
  // visibility's lattice: 9.8 against 9.3).
  double sun_light_gain = 0.0;
};

void PrintTo(const KhronosCase& c, std::ostream* os) {
  *os << c.model;
}

class KhronosGlass : public ::testing::TestWithParam<KhronosCase> {};

TEST_P(KhronosGlass, OursHoldsToThePathTracerOverTheRelic) {
  const KhronosCase& c = GetParam();
  HOLO_REQUIRE_SHARED_DATA("models/" + c.model);
  const Size size = evaluationSize();
  for (const std::string& panorama : size.panoramas) {
    HOLO_REQUIRE_SHARED_DATA(panorama);
    const ReflectionScene scene = khronosScene(c.model, panorama);
    ViewOptions view;
    view.width = view.height = size.pixels;
    const CameraModel camera = viewCamera(view, scene);
    cv::Mat glass;
    const cv::Mat mask = relicPixels(scene.relic, camera, &glass);
    ASSERT_GT(cv::countNonZero(mask), size.pixels * size.pixels / 20) << "the relic is not in the view";
    const cv::Mat truth = renderView("gt", scene, camera, size.gt_spp);
    const cv::Mat ours = renderView("ours", scene, camera, 1);
    const double codes = meanCodes(ours, truth, mask);
    // The panorama's sun left in the 9-coefficient diffuse light, for the figure's comparison.
    const double without_sun_light = meanCodes(renderView("ours", scene, camera, 1, false), truth, mask);
    // Apart, for the figure: the pixels whose first hit is glass and the opaque ones.
    const cv::Mat opaque = mask & ~glass;
    std::printf(
        "%s under %s, %d^2, truth %d spp: ours %.2f sRGB codes from the truth over %d relic pixels "
        "(%.2f over its %d glass pixels, %.2f over its %d opaque ones; %.2f without the sun light)\n",
        c.model.c_str(), panorama.c_str(), size.pixels, size.gt_spp, codes, cv::countNonZero(mask),
        meanCodes(ours, truth, glass), cv::countNonZero(glass), meanCodes(ours, truth, opaque),
        cv::countNonZero(opaque), without_sun_light);
    EXPECT_LT(codes, fullEvaluation() ? 8.0 : c.ci_bar) << panorama;
    if (c.sun_light_gain > 0.0 && panorama == "hdri/rooitou_park_1k.hdr") {  // the one with a sun
      EXPECT_GT(without_sun_light, c.sun_light_gain * codes) << "the sun light switched off, " << panorama;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Models, KhronosGlass,
                         ::testing::Values(KhronosCase{"khronos_glass_hurricane_candle_holder.glb", 13.0,
                                                       1.1},
                                           KhronosCase{"khronos_transmission_roughness_test.glb", 11.0},
                                           KhronosCase{"khronos_attenuation_test.glb", 5.0},
                                           KhronosCase{"khronos_clearcoat_wicker.glb", 9.0, 1.4}));

// The candle inside the hurricane glass: the pixels whose view ray meets the glass first and the
// candle behind it (the relic without its glass). Ours must show the candle there as the truth
// does; the adversary that leaves what stands inside out (the relic without the candle, the hall
// seen through the glass instead) must be measurably further from the truth on the same pixels.
// The bar at 256^2 (HOLO_FULL_EVAL=1) is the 8 codes, not met (8.58).
TEST(KhronosGlassCandle, TheCandleIsSeenThroughTheGlassAsInTheTruth) {
  const std::string model = "khronos_glass_hurricane_candle_holder.glb";
  HOLO_REQUIRE_SHARED_DATA("models/" + model);
  const Size size = evaluationSize();
  HOLO_REQUIRE_SHARED_DATA(size.panoramas.front());
  const ReflectionScene scene = khronosScene(model, size.panoramas.front());
  ViewOptions view;
  view.width = view.height = size.pixels;
  const CameraModel camera = viewCamera(view, scene);

  // The relic split into what transmits and what does not.
  Model glass = scene.relic, inside = scene.relic;
  const auto keep = [](Model& m, bool transmissive) {
    std::erase_if(m.meshes, [&](const TriangleMesh& mesh) {
      return (m.materials[std::size_t(mesh.material)].transmission > 0.0f) != transmissive;
    });
  };
  keep(glass, true);
  keep(inside, false);
  ASSERT_FALSE(glass.meshes.empty());
  ASSERT_FALSE(inside.meshes.empty());
  const reflect::RenderScene glass_scene(glass, {}), relic_scene(scene.relic, {}), inside_scene(inside, {});
  cv::Mat candle(camera.height(), camera.width(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x) {
      const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(y)));
      const RayHit first = relic_scene.relicOnly().intersect(ray);
      const RayHit glass_hit = glass_scene.relicOnly().intersect(ray);
      if (first.hit() && glass_hit.hit() && std::abs(first.t - glass_hit.t) < 1e-6f &&
          inside_scene.relicOnly().intersect(ray).hit())
        candle.at<std::uint8_t>(y, x) = 255;
    }
  const int pixels = cv::countNonZero(candle);
  ASSERT_GT(pixels, size.pixels * size.pixels / 100) << "no candle behind the glass in the view";

  const cv::Mat truth = renderView("gt", scene, camera, size.gt_spp);
  const cv::Mat ours = renderView("ours", scene, camera, 1);
  ReflectionScene dropped = khronosScene(model, size.panoramas.front());
  dropped.relic = glass;
  const cv::Mat without = renderView("ours", dropped, camera, 1);
  const double codes = meanCodes(ours, truth, candle), dropped_codes = meanCodes(without, truth, candle);
  std::printf(
      "candle seen through the glass (%d pixels, %d^2): ours %.2f sRGB codes from the truth, "
      "the candle left out %.2f\n",
      pixels, size.pixels, codes, dropped_codes);
  // Measured at CI size: 11.9 (the truth's own noise there: 8.6; 17.4 with the sun in the 9
  // coefficients inside the glass), the candle left out 25.5; at 256^2 8.6 (14.2 with the sun in
  // the coefficients) and 24.7. The glass's textures read at the entry only: 40.9 (the candle hidden).
  EXPECT_LT(codes, fullEvaluation() ? 8.0 : 13.5);
  EXPECT_GT(dropped_codes, 1.3 * codes);
}

// Why the clearcoat wicker departs from its truth under the park's sun (opt-in, HOLO_FULL_EVAL=1;
// docs/materials.md): the model as it is, then one thing taken away from both renderers or from
// ours alone (the last: the sun light switched off), 128^2 under rooitou park, truth 256 spp.
TEST(KhronosWicker, WhatTheSunDoes) {
  if (!fullEvaluation()) GTEST_SKIP() << "HOLO_FULL_EVAL=1 renders the wicker's figures";
  const std::string model = "khronos_clearcoat_wicker.glb", panorama = "hdri/rooitou_park_1k.hdr";
  HOLO_REQUIRE_SHARED_DATA("models/" + model);
  HOLO_REQUIRE_SHARED_DATA(panorama);
  constexpr int kPixels = 128, kSpp = 256;
  constexpr float kSunLuminance = 50.0f;  // the sun: the panorama's pixels brighter than this
  const auto keep = [&](cv::Mat& pano, bool sun) {
    for (int y = 0; y < pano.rows; ++y)
      for (int x = 0; x < pano.cols; ++x) {
        cv::Vec3f& v = pano.at<cv::Vec3f>(y, x);
        const float l = 0.0722f * v[0] + 0.7152f * v[1] + 0.2126f * v[2];
        if (sun && l < kSunLuminance) v = cv::Vec3f(0.0f, 0.0f, 0.0f);
        if (!sun && l > kSunLuminance) v *= kSunLuminance / l;
      }
  };
  const auto diffuseOnly = [](Model& relic) {
    for (Material& m : relic.materials) {
      m.clearcoat = m.specular = m.metallic = 0.0f;
      m.metallic_roughness_texture = {};
    }
  };
  const std::vector<std::string> variants = {"as it is",
                                             "no self-occlusion in ours",
                                             "the sun clamped to the sky",
                                             "no clearcoat",
                                             "the sun alone",
                                             "the sun alone, diffuse only",
                                             "the sun alone, diffuse only, no normal map",
                                             "the sun alone, diffuse only, no occlusion texture",
                                             "no sun light in ours (the sun in the 9 coefficients)"};
  std::vector<double> codes;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    ReflectionScene scene = khronosScene(model, panorama);
    MethodSettings ours;
    ours.with_visitors = false;
    if (v == 1) ours.tracer.evaluation.self_occlusion = false;
    if (v == 8) ours.tracer.evaluation.sun_light = false;
    if (v == 2) keep(scene.panorama, false);
    if (v == 3)
      for (Material& m : scene.relic.materials) m.clearcoat = 0.0f;
    if (v >= 4) keep(scene.panorama, true);
    if (v >= 5) diffuseOnly(scene.relic);
    for (Material& m : scene.relic.materials) {
      if (v == 6) m.normal_texture = {};
      if (v == 7) m.occlusion_texture = {};
    }
    ViewOptions view;
    view.width = view.height = kPixels;
    const CameraModel camera = viewCamera(view, scene);
    const cv::Mat mask = relicPixels(scene.relic, camera);
    const cv::Mat truth = renderView("gt", scene, camera, kSpp);
    const cv::Mat image = renderMethod("ours", scene, camera, ours).image;
    double ours_sum = 0, truth_sum = 0;
    for (int y = 0; y < kPixels; ++y)
      for (int x = 0; x < kPixels; ++x)
        if (mask.at<std::uint8_t>(y, x))
          for (int c = 0; c < 3; ++c) {
            ours_sum += image.at<cv::Vec3f>(y, x)[c];
            truth_sum += truth.at<cv::Vec3f>(y, x)[c];
          }
    codes.push_back(meanCodes(image, truth, mask));
    std::printf("wicker, %s: %.2f sRGB codes, mean ours/truth %.3f\n", variants[v].c_str(), codes.back(),
                ours_sum / truth_sum);
  }
  EXPECT_LT(codes[2], 0.5 * codes[8]);   // the sun in the 9 coefficients is the cause
  EXPECT_LT(codes[0], 0.75 * codes[8]);  // the sun light takes it out (0.60 at 256^2)
  EXPECT_GT(codes[3], 0.8 * codes[0]);   // the clearcoat is not
}

}  // namespace
}  // namespace holo::eval

namespace holo::eval {
namespace {

// A path-traced truth of `scene` seen by `camera` at `spp` samples with sampling seed `seed`, kept
// in `file` between runs where one is named (a long truth is rendered once, in the background,
// and read by every later variant that changes ours alone).
cv::Mat cachedTruth(const ReflectionScene& scene, const CameraModel& camera, int spp, std::uint64_t seed,
                    const std::string& file) {
  cv::Mat truth(camera.height(), camera.width(), CV_32FC3);
  if (!file.empty())
    if (std::FILE* f = std::fopen(file.c_str(), "rb")) {
      const bool complete = std::fread(truth.data, truth.elemSize(), truth.total(), f) == truth.total();
      std::fclose(f);
      if (complete) return truth;
    }
  MethodSettings settings;
  settings.spp = spp;
  settings.with_visitors = false;
  settings.seed = seed;
  truth = renderMethod("gt", scene, camera, settings).image;
  if (!file.empty())
    if (std::FILE* f = std::fopen(file.c_str(), "wb")) {
      std::fwrite(truth.data, truth.elemSize(), truth.total(), f);
      std::fclose(f);
    }
  return truth;
}

// Where a model's codes are (opt-in, HOLO_KHRONOS_SPLIT=model.glb; docs/materials.md, "Where the
// remaining codes are"): the relic's pixels split by
// what the pixel's ray meets (its first material; for glass, whether the straight ray goes on to
// an opaque part and whether it enters in the lowest 30% of the relic's height), with the mean
// codes, each channel's signed mean (ours - truth) and both images' linear means per channel.
void splitCodes(const std::string& model, const std::string& panorama, int pixels, int spp,
                const std::function<void(ReflectionScene&)>& edit, MethodSettings ours_settings,
                const std::vector<std::pair<std::uint64_t, std::string>>& truth_seeds, int reference_spp,
                const std::string& reference_file) {
  ReflectionScene scene = khronosScene(model, panorama);
  if (edit) edit(scene);
  ViewOptions view;
  view.width = view.height = pixels;
  const CameraModel camera = viewCamera(view, scene);
  Model inside = scene.relic;
  std::erase_if(inside.meshes, [&](const TriangleMesh& mesh) {
    return inside.materials[std::size_t(mesh.material)].transmission > 0.0f;
  });
  const reflect::RenderScene relic_scene(scene.relic, {}), inside_scene(inside, {});
  const Bounds3 box = scene.relic.bounds();
  // The truth: the mean of independent truths of `spp` samples each (one per seed), as one truth of
  // their samples together.
  cv::Mat truth = cv::Mat::zeros(pixels, pixels, CV_32FC3);
  for (const auto& [seed, file] : truth_seeds) truth += cachedTruth(scene, camera, spp, seed, file);
  truth /= double(truth_seeds.size());
  spp *= int(truth_seeds.size());
  ours_settings.with_visitors = false;
  const cv::Mat ours = renderMethod("ours", scene, camera, ours_settings).image;
  const float exposure = reflect::autoExposure(truth);
  const cv::Mat a = reflect::toneMap(ours, exposure), b = reflect::toneMap(truth, exposure);
  // reference_spp > 0: a second, independent truth (seed 2), against which both ours and the
  // truth are measured too: what of ours' codes is the truth's own noise.
  cv::Mat reference;
  if (reference_spp > 0)
    reference = reflect::toneMap(cachedTruth(scene, camera, reference_spp, 2, reference_file), exposure);
  if (const char* dump = std::getenv("HOLO_KHRONOS_DUMP")) {
    cv::Mat diff(a.size(), CV_8UC3);
    for (int y = 0; y < a.rows; ++y)
      for (int x = 0; x < a.cols; ++x)
        for (int c = 0; c < 3; ++c)
          diff.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<std::uint8_t>(
              128 + 2 * (int(a.at<cv::Vec3b>(y, x)[c]) - int(b.at<cv::Vec3b>(y, x)[c])));
    cv::Mat row, big;
    cv::hconcat(std::vector<cv::Mat>{a, b, diff}, row);
    cv::resize(row, big, {}, 3, 3, cv::INTER_NEAREST);
    const std::string name = std::string(dump) + "/" + panorama.substr(5, 6) + ".png";
    cv::imwrite(name, big);
  }
  struct Sum {
    int n = 0;
    double abs = 0, signed_codes[3] = {}, ours_lin[3] = {}, truth_lin[3] = {};
    double ours_to_reference = 0, truth_to_reference = 0;
  };
  std::map<std::string, Sum> sums;
  int total = 0;
  for (int y = 0; y < pixels; ++y)
    for (int x = 0; x < pixels; ++x) {
      const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(y)));
      const RayHit hit = relic_scene.relicOnly().intersect(ray);
      if (!hit.hit()) continue;
      const Material& m = relic_scene.relicGltfMaterial(hit, relic_scene.relicOnly());
      std::string label = m.name;
      const vec3 p = ray.origin + hit.t * ray.direction;
      if (m.transmissive())
        label += inside_scene.relicOnly().intersect(ray).hit() ? " / opaque behind" : " / no opaque behind";
      label += (p.y - box.lo.y) < 0.3f * (box.hi.y - box.lo.y) ? " / low 30%" : " / upper";
      if (!m.transmissive()) {
        const reflect::SurfacePoint sp =
            reflect::resolveSurface(relic_scene, relic_scene.relicOnly(), ray, hit, 0.0f);
        label += sp.material.metallic > 0.5f ? " / metal" : " / dielectric";
        label += sp.material.roughness < 0.3f ? " smooth" : " rough";
        label += sp.normal.y > 0.5f ? " up" : " side";
      }
      for (const std::string& key : {label, std::string("all")}) {
        Sum& s = sums[key];
        ++s.n;
        for (int c = 0; c < 3; ++c) {
          const double d = double(a.at<cv::Vec3b>(y, x)[c]) - double(b.at<cv::Vec3b>(y, x)[c]);
          s.abs += std::abs(d) / 3.0;
          s.signed_codes[c] += d;
          s.ours_lin[c] += ours.at<cv::Vec3f>(y, x)[c];
          s.truth_lin[c] += truth.at<cv::Vec3f>(y, x)[c];
          if (reference.empty()) continue;
          const double r = reference.at<cv::Vec3b>(y, x)[c];
          s.ours_to_reference += std::abs(double(a.at<cv::Vec3b>(y, x)[c]) - r) / 3.0;
          s.truth_to_reference += std::abs(double(b.at<cv::Vec3b>(y, x)[c]) - r) / 3.0;
        }
      }
      ++total;
    }
  for (const auto& [label, s] : sums) {
    if (!reference.empty()) {
      // The truth's own noise: an independent truth of reference_spp samples differs from it by
      // sqrt(1 + spp / reference_spp) times it (sqrt(2) at as many samples); taken out of ours'
      // codes in quadrature (as docs/reflect.md removes it from an RMSE).
      const double noise = s.truth_to_reference / s.n / std::sqrt(1.0 + double(spp) / reference_spp),
                   codes = s.abs / s.n;
      std::printf(
          "  %-58s against the reference truth: ours %6.2f codes, the truth %6.2f; the truth's own noise "
          "%.2f, ours with it removed %6.2f\n",
          label.c_str(), s.ours_to_reference / s.n, s.truth_to_reference / s.n, noise,
          std::sqrt(std::max(codes * codes - noise * noise, 0.0)));
    }
    std::printf(
        "  %-58s %5d px  %6.2f codes (share of the total %5.2f)  signed RGB %+6.1f %+6.1f %+6.1f  "
        "linear ours %.3f %.3f %.3f truth %.3f %.3f %.3f\n",
        label.c_str(), s.n, s.abs / s.n, s.abs / total, s.signed_codes[2] / s.n, s.signed_codes[1] / s.n,
        s.signed_codes[0] / s.n, s.ours_lin[2] / s.n, s.ours_lin[1] / s.n, s.ours_lin[0] / s.n,
        s.truth_lin[2] / s.n, s.truth_lin[1] / s.n, s.truth_lin[0] / s.n);
  }
}

TEST(KhronosSplit, WhereTheCodesAre) {
  const char* model = std::getenv("HOLO_KHRONOS_SPLIT");
  if (model == nullptr) GTEST_SKIP() << "HOLO_KHRONOS_SPLIT=model.glb splits its codes";
  const char* px = std::getenv("HOLO_KHRONOS_PIXELS");
  const char* variant_env = std::getenv("HOLO_KHRONOS_VARIANT");
  const std::string variant = variant_env ? variant_env : "";
  const int pixels = px ? std::atoi(px) : 128;
  for (const std::string panorama : {"hdri/rooitou_park_1k.hdr", "hdri/st_fagans_interior_1k.hdr"}) {
    std::printf("%s under %s, %d^2, variant '%s'\n", model, panorama.c_str(), pixels, variant.c_str());
    std::function<void(ReflectionScene&)> edit;
    MethodSettings settings;
    if (variant == "no-attenuation")
      edit = [](ReflectionScene& s) {
        for (Material& m : s.relic.materials) m.attenuation_distance = std::numeric_limits<float>::infinity();
      };
    if (variant == "no-candle")
      edit = [](ReflectionScene& s) {
        std::erase_if(s.relic.meshes, [&](const TriangleMesh& mesh) {
          return s.relic.materials[std::size_t(mesh.material)].transmission == 0.0f;
        });
      };
    if (variant == "white-glass")
      edit = [](ReflectionScene& s) {
        for (Material& m : s.relic.materials)
          if (m.transmissive()) {
            m.base_colour_texture = {};
            m.base_colour = vec3(1.0f);
          }
      };
    if (variant == "smooth-glass")  // the glass's roughness factor 0 (its texture scales it)
      edit = [](ReflectionScene& s) {
        for (Material& m : s.relic.materials)
          if (m.transmissive()) m.roughness = 0.0f;
      };
    if (variant == "sun-clamped" || variant == "sun-only")
      edit = [&](ReflectionScene& s) {
        for (int y = 0; y < s.panorama.rows; ++y)
          for (int x = 0; x < s.panorama.cols; ++x) {
            cv::Vec3f& v = s.panorama.at<cv::Vec3f>(y, x);
            const float l = 0.0722f * v[0] + 0.7152f * v[1] + 0.2126f * v[2];
            if (variant == "sun-only" && l < 50.0f) v = cv::Vec3f(0.0f, 0.0f, 0.0f);
            if (variant == "sun-clamped" && l > 50.0f) v *= 50.0f / l;
          }
      };
    if (variant.rfind("depth-", 0) == 0) settings.tracer.refraction_depth = std::atoi(variant.c_str() + 6);
    if (variant.rfind("sky-only", 0) == 0 || variant == "ground-only")  // the other half black in both
      edit = [&](ReflectionScene& s) {
        for (int y = 0; y < s.panorama.rows; ++y)
          if ((variant != "ground-only") == (y >= s.panorama.rows / 2))
            s.panorama.row(y).setTo(cv::Scalar(0, 0, 0));
        if (variant == "sky-only-clamped")
          for (int y = 0; y < s.panorama.rows; ++y)
            for (int x = 0; x < s.panorama.cols; ++x) {
              cv::Vec3f& v = s.panorama.at<cv::Vec3f>(y, x);
              const float l = 0.0722f * v[0] + 0.7152f * v[1] + 0.2126f * v[2];
              if (l > 50.0f) v *= 50.0f / l;
            }
      };
    if (variant == "sky-only-depth-32") settings.tracer.refraction_depth = 32;
    if (variant == "stride-1") settings.tracer.refraction_stride = 1;
    if (variant.rfind("branch-", 0) == 0) {  // branch-RAYS-WEIGHT: the light reflected inside followed
      settings.tracer.refraction_branch_rays = std::atoi(variant.c_str() + 7);
      settings.tracer.refraction_branch_weight = std::stof(variant.substr(variant.find('-', 7) + 1));
    }
    if (variant == "no-sun-light") settings.tracer.evaluation.sun_light = false;
    if (variant == "no-self-occlusion") settings.tracer.evaluation.self_occlusion = false;
    if (variant == "no-interreflection") settings.tracer.relic_interreflection = false;
    if (variant == "no-specular")
      edit = [](ReflectionScene& s) {
        for (Material& m : s.relic.materials)
          if (!m.transmissive()) m.specular = 0.0f;
      };
    if (variant == "fine-backdrop")  // meshes of at most 8 triangles split 4-way 5 times (1024 each)
      edit = [](ReflectionScene& s) {
        for (TriangleMesh& mesh : s.relic.meshes) {
          if (mesh.triangles.size() > 8) continue;
          for (int level = 0; level < 5; ++level) {
            std::vector<uvec3> triangles;
            const auto mid = [&](std::uint32_t a, std::uint32_t b) {
              mesh.positions.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
              if (!mesh.normals.empty())
                mesh.normals.push_back(glm::normalize(mesh.normals[a] + mesh.normals[b]));
              if (!mesh.tangents.empty()) mesh.tangents.push_back(mesh.tangents[a]);
              if (!mesh.uvs.empty()) mesh.uvs.push_back(0.5f * (mesh.uvs[a] + mesh.uvs[b]));
              if (!mesh.uvs1.empty()) mesh.uvs1.push_back(0.5f * (mesh.uvs1[a] + mesh.uvs1[b]));
              return std::uint32_t(mesh.positions.size() - 1);
            };
            for (const uvec3& t : mesh.triangles) {
              const std::uint32_t ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
              triangles.push_back({t.x, ab, ca});
              triangles.push_back({ab, t.y, bc});
              triangles.push_back({ca, bc, t.z});
              triangles.push_back({ab, bc, ca});
            }
            mesh.triangles = triangles;
          }
        }
      };
    if (const char* only = std::getenv("HOLO_KHRONOS_PANORAMA");
        only && panorama.find(only) == std::string::npos)
      continue;
    const char* truth_spp = std::getenv("HOLO_KHRONOS_TRUTH_SPP");
    const int spp = truth_spp ? std::atoi(truth_spp) : 256;
    // HOLO_KHRONOS_TRUTH_SEEDS=1,3,4,5: the truth is the mean of truths of as many seeds (each kept
    // in the cache on its own: each can be rendered in a process of its own, beside the others).
    std::vector<std::uint64_t> truth_seeds;
    if (const char* seeds = std::getenv("HOLO_KHRONOS_TRUTH_SEEDS")) {
      std::string list = seeds;
      for (std::size_t at = 0; at < list.size();) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        truth_seeds.push_back(std::stoull(list.substr(at, comma - at)));
        at = comma + 1;
      }
    }
    if (truth_seeds.empty()) truth_seeds.push_back(1);
    const char* reference_env = std::getenv("HOLO_KHRONOS_REFERENCE_SPP");
    const int reference_spp = reference_env ? std::atoi(reference_env) : 0;
    // The truths' file names: model, panorama, size, samples, the scene's edit, the seed past 1.
    const auto cacheFile = [&](int samples, const std::string& seed_suffix) {
      const char* cache = std::getenv("HOLO_KHRONOS_TRUTH_CACHE");
      if (cache == nullptr) return std::string();
      return std::string(cache) + "/" + model + "-" + panorama.substr(5, 6) + "-" + std::to_string(pixels) +
             "-" + std::to_string(samples) + (edit ? "-" + variant : std::string()) + seed_suffix + ".f32";
    };
    const auto seedSuffix = [](std::uint64_t seed) {
      return seed == 1 ? std::string() : "-seed" + std::to_string(seed);
    };
    std::vector<std::pair<std::uint64_t, std::string>> truths;
    for (const std::uint64_t seed : truth_seeds) truths.emplace_back(seed, cacheFile(spp, seedSuffix(seed)));
    splitCodes(model, panorama, pixels, spp, edit, settings, truths, reference_spp,
               cacheFile(reference_spp, seedSuffix(2)));
  }
}

}  // namespace
}  // namespace holo::eval
