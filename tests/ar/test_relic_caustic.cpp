// The caustic of a glass relic on the real receiver in the AR composite (relic_caustic.hpp): a glass
// ball standing on the plane of ar_test_scene.hpp under its small sun focuses the sun beside it;
// the composite's real pixels there brighten as the path-traced mixed scene's do, and the plan
// traces nothing for an opaque relic.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <glm/gtc/constants.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_test_scene.hpp"
#include "holo/ar/ar_view.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/ar/relic_caustic.hpp"
#include "holo/core/image.hpp"
#include "holo/core/shapes.hpp"
#include "holo/core/stats.hpp"

namespace holo::ar {
namespace {

using test::luminance;
using test::samples;

Model glassBall() {
  Model relic = test::sphereRelic();
  relic.meshes[0] = makeSphere(0.12f, 32, 64);
  for (vec3& p : relic.meshes[0].positions) p += vec3(0.0f, 0.12f, 0.0f);
  Material& glass = relic.materials[0];
  glass.base_colour = vec3(1.0f);
  glass.transmission = 1.0f;
  glass.thickness = 0.1f;
  glass.ior = 1.5f;
  return relic;
}

// From above the ball's sun side; the sun (+X, 38 degrees up) throws the caustic towards -X.
CameraModel causticCamera() {
  constexpr int kSize = 40;
  const float fov = glm::radians(40.0f);
  return CameraModel(Intrinsics::fromFov(kSize, kSize, fov, fov),
                     lookAtCameraToWorld({-0.05f, 0.75f, 0.35f}, {-0.12f, 0.0f, 0.0f}));
}

struct CausticScene {
  cv::Mat panorama = test::sunnyPanorama();
  reflect::Environment environment{panorama};
  Model relic = glassBall();
  LocalScene local{test::plane(), relic, environment};
  CameraModel view = causticCamera();
  // The camera's image (the plane alone) and the truth (plane and ball), path traced.
  cv::Mat real = renderLocalScene(local, SceneContent::kReal, view, samples(64, 7)).radiance;
  CompositeImage truth = renderLocalScene(local, SceneContent::kMixed, view, samples(512, 11));
  // The same again with other samples: the caustic's pixels are chosen on `truth`, where its noise
  // lifts them (a selection bias of about a fifth), and measured against this one.
  CompositeImage reference = renderLocalScene(local, SceneContent::kMixed, view, samples(512, 12));
};

// The pixels the caustic brightens in the truth (real pixels above 1.5x the camera's image).
cv::Mat causticPixels(const CausticScene& s) {
  cv::Mat mask(s.real.size(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < s.real.rows; ++y)
    for (int x = 0; x < s.real.cols; ++x)
      if (s.truth.relic_coverage.at<float>(y, x) == 0.0f &&
          luminance(rgbAt(s.truth.radiance, x, y)) > 1.5f * luminance(rgbAt(s.real, x, y)))
        mask.at<std::uint8_t>(y, x) = 255;
  return mask;
}

struct CausticError {
  double rmse = 0, mean_change = 0;
};
CausticError errorOver(const cv::Mat& composite, const CausticScene& s, const cv::Mat& mask) {
  CausticError e;
  int n = 0;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<std::uint8_t>(y, x)) {
        const double c = luminance(rgbAt(composite, x, y)), t = luminance(rgbAt(s.reference.radiance, x, y));
        e.rmse += (c - t) * (c - t);
        e.mean_change += c - luminance(rgbAt(s.real, x, y));
        ++n;
      }
  e.rmse = std::sqrt(e.rmse / std::max(n, 1));
  e.mean_change /= std::max(n, 1);
  return e;
}

// The brightest real pixel of (image - real), 3x3 box-filtered.
cv::Point peakOfChange(const cv::Mat& image, const CausticScene& s) {
  cv::Mat change(image.size(), CV_32FC1, cv::Scalar(0));
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (s.truth.relic_coverage.at<float>(y, x) == 0.0f)
        change.at<float>(y, x) = luminance(rgbAt(image, x, y)) - luminance(rgbAt(s.real, x, y));
  cv::Mat box;
  cv::blur(change, box, cv::Size(3, 3));
  cv::Point peak;
  cv::minMaxLoc(box, nullptr, nullptr, nullptr, &peak);
  return peak;
}

RelicCausticSettings photons(std::uint64_t n) {
  RelicCausticSettings c;
  c.photons = n;
  return c;
}

TEST(RelicCaustic, TheCompositeBrightensWhereTheTruthsCausticFalls) {
  const CausticScene s;
  const cv::Mat mask = causticPixels(s);
  ASSERT_GT(cv::countNonZero(mask), 8) << "the ball focuses the sun onto the plane in view";
  const std::optional<RelicCaustic> caustic = traceRelicCaustic(s.relic, s.environment, photons(1u << 16));
  ASSERT_TRUE(caustic.has_value());
  EXPECT_GT(caustic->image().stored, 1000u);
  // The adversary: the same composite with no caustic light at all (an empty map, the glass paths
  // still left to it), and the composite without the light tracer (BSDF sampling alone finds the
  // sun through the glass).
  reflect::CausticImage dark = caustic->image();
  dark.irradiance = cv::Mat(dark.irradiance.size(), dark.irradiance.type(), cv::Scalar::all(0));
  const RelicCaustic none(dark, RelicCausticSettings{}.receiver_tolerance,
                          RelicCausticSettings{}.receiver_min_cos);
  const CompositeSettings spp16 = samples(16, 3);
  const cv::Mat with =
      renderComposite(s.local, s.view, s.real, spp16, cv::Mat(), cv::Mat(), &*caustic).radiance;
  const cv::Mat without =
      renderComposite(s.local, s.view, s.real, spp16, cv::Mat(), cv::Mat(), &none).radiance;
  const cv::Mat traced = renderComposite(s.local, s.view, s.real, spp16).radiance;
  const CausticError e_with = errorOver(with, s, mask), e_without = errorOver(without, s, mask),
                     e_traced = errorOver(traced, s, mask),
                     e_truth = errorOver(s.reference.radiance, s, mask);
  std::cout << "caustic pixels " << cv::countNonZero(mask) << ", true mean change " << e_truth.mean_change
            << "; light tracer: change " << e_with.mean_change << " rmse " << e_with.rmse
            << "; no caustic: change " << e_without.mean_change << " rmse " << e_without.rmse
            << "; BSDF sampling alone: change " << e_traced.mean_change << " rmse " << e_traced.rmse << "\n";
  ASSERT_GT(e_truth.mean_change, 0.0);
  EXPECT_NEAR(e_with.mean_change / e_truth.mean_change, 1.0, 0.15);
  EXPECT_LT(e_without.mean_change, 0.0) << "without the caustic the ball only shadows there";
  EXPECT_LT(e_with.rmse, 0.5 * e_without.rmse);
  EXPECT_LT(e_with.rmse, 0.5 * e_traced.rmse);
  // The change region holds the caustic's pixels.
  const cv::Mat region = compositeRegion(s.local, s.view, s.real, ArViewSettings{}, &*caustic);
  const cv::Mat bound_alone = compositeRegion(s.local, s.view, s.real, ArViewSettings{});
  std::cout << "caustic pixels outside the change region: " << cv::countNonZero(mask & ~region)
            << " (without the caustic's cells " << cv::countNonZero(mask & ~bound_alone) << ")\n";
  EXPECT_EQ(cv::countNonZero(mask & ~region), 0);
  const cv::Point truth_peak = peakOfChange(s.reference.radiance, s), peak = peakOfChange(with, s);
  std::cout << "peak of the change: truth (" << truth_peak.x << ", " << truth_peak.y << "), composite ("
            << peak.x << ", " << peak.y << ")\n";
  EXPECT_LE(std::hypot(peak.x - truth_peak.x, peak.y - truth_peak.y), 1.5);
}

TEST(RelicCaustic, AnOpaqueRelicOrOneBelowTheReceiverTracesNoPhoton) {
  const cv::Mat panorama = test::sunnyPanorama();
  const reflect::Environment environment(panorama);
  auto& traced = stats::counter("Caustics/Live photons traced");
  const std::int64_t before = traced.load();
  EXPECT_FALSE(traceRelicCaustic(test::sphereRelic(), environment, photons(1u << 12)).has_value());
  RelicCausticSettings above = photons(1u << 12);
  above.receiver_height = 0.05f;  // the ball's foot below the receiver
  EXPECT_FALSE(traceRelicCaustic(glassBall(), environment, above).has_value());
  RelicCausticSettings off = photons(1u << 12);
  off.enabled = false;
  EXPECT_FALSE(traceRelicCaustic(glassBall(), environment, off).has_value());
  EXPECT_EQ(traced.load(), before);
  const std::optional<RelicCaustic> glass = traceRelicCaustic(glassBall(), environment, photons(1u << 12));
  ASSERT_TRUE(glass.has_value());
  EXPECT_EQ(glass->image().traced, 1u << 12);
}

}  // namespace
}  // namespace holo::ar
