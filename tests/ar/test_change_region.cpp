// The change region (change_region.hpp) against brute force: delta path tracing of every pixel at
// many samples changes no pixel outside the region by a displayed amount, while a region that
// holds only the relic's own pixels (the adversary) leaves the shadow out; a relic wholly below
// the real surface's horizon changes nothing, exactly, and the region holds no real pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "ar_test_scene.hpp"
#include "holo/ar/change_region.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/core/image.hpp"

namespace holo::ar {
namespace {

constexpr float kExposure = 0.4f;  // the plane in the sun at about code 190

float code(float radiance) {
  return 255.0f * linearToSrgb(kExposure * radiance);
}

// Per pixel, the largest displayed change over the channels of the brute force's mean against the
// background, less three standard errors of that mean (from batches): what certainly shows.
struct BruteForce {
  cv::Mat certain_codes;  // CV_32FC1
  cv::Mat coverage;       // CV_32FC1
};

BruteForce bruteForce(const LocalScene& scene, const CameraModel& view, const cv::Mat& background) {
  constexpr int kBatches = 16, kBatchSpp = 32;
  CompositeSettings s;
  s.spp = kBatchSpp;
  std::vector<cv::Mat> batches;
  BruteForce out;
  out.coverage = cv::Mat(background.size(), CV_32FC1, cv::Scalar(0));
  for (int b = 0; b < kBatches; ++b) {
    s.first_sample = b * kBatchSpp;
    const CompositeImage image = renderComposite(scene, view, background, s);
    batches.push_back(image.radiance);
    out.coverage = cv::max(out.coverage, image.relic_coverage);
  }
  out.certain_codes = cv::Mat(background.size(), CV_32FC1, cv::Scalar(0));
  for (int y = 0; y < background.rows; ++y)
    for (int x = 0; x < background.cols; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0, sq = 0;
        for (const cv::Mat& m : batches) {
          const double v = m.at<cv::Vec3f>(y, x)[c];
          sum += v;
          sq += v * v;
        }
        const double mean = sum / kBatches;
        const double standard_error = std::sqrt(std::max(0.0, sq / kBatches - mean * mean) / (kBatches - 1));
        const float b = background.at<cv::Vec3f>(y, x)[c];
        const float shown = std::abs(code(static_cast<float>(mean)) - code(b));
        // The code's slope at the mean turns the radiance's standard error into codes.
        const float slope =
            std::abs(code(static_cast<float>(mean + standard_error)) - code(static_cast<float>(mean)));
        out.certain_codes.at<float>(y, x) = std::max(out.certain_codes.at<float>(y, x), shown - 3.0f * slope);
      }
  return out;
}

// The pixels outside `region` whose change certainly shows by more than `codes`.
int skippedVisible(const BruteForce& brute, const cv::Mat& region, float codes) {
  return cv::countNonZero((brute.certain_codes > codes) & (region == 0));
}

TEST(ChangeRegion, NoPixelOutsideItChangesVisiblyByBruteForceAndTheShadowIsInIt) {
  const cv::Mat panorama = test::sunnyPanorama();
  const reflect::Environment environment(panorama);
  const LocalScene scene(test::plane(), test::sphereRelic(), environment);
  const CameraModel view = test::camera();
  CompositeSettings real_settings;
  real_settings.spp = 64;
  const cv::Mat background = renderLocalScene(scene, SceneContent::kReal, view, real_settings).radiance;

  const ChangeRegionSettings settings{.negligible_codes = 0.5f, .exposure = kExposure};
  const cv::Mat region = changeRegion(scene, view, background, settings);
  const int traced = cv::countNonZero(region);
  const BruteForce brute = bruteForce(scene, view, background);
  EXPECT_EQ(skippedVisible(brute, region, settings.negligible_codes), 0);
  // The region holds every pixel a sample of the relic met, and leaves pixels out (it pays).
  EXPECT_EQ(cv::countNonZero((brute.coverage > 0.0f) & (region == 0)), 0);
  EXPECT_LT(traced, static_cast<int>(region.total()) * 9 / 10);
  // The adversary: the relic's own pixels (and their neighbours) only, as a region would without
  // the bound; it skips the shadow.
  cv::Mat relic_only = brute.coverage > 0.0f;
  cv::dilate(relic_only, relic_only, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  const int shadow_skipped = skippedVisible(brute, relic_only, settings.negligible_codes);
  EXPECT_GT(shadow_skipped, 20);
  // Tracing the region gives the brute force's samples there and the background elsewhere.
  CompositeSettings pass;
  pass.spp = 4;
  const CompositeImage all = renderComposite(scene, view, background, pass);
  const CompositeImage traced_only = renderComposite(scene, view, background, pass, region);
  cv::Mat expected = background.clone();
  all.radiance.copyTo(expected, region);
  EXPECT_EQ(cv::norm(traced_only.radiance, expected, cv::NORM_INF), 0.0);
  EXPECT_LT(traced_only.rays, all.rays);
  std::cout << "traced " << traced << " of " << region.total() << " pixels; the relic-only region skips "
            << shadow_skipped << " visibly changed pixels\n";
}

TEST(ChangeRegion, ARelicBelowTheSurfacesHorizonChangesNothingAndNoRealPixelIsInIt) {
  const cv::Mat panorama = test::sunnyPanorama();
  const reflect::Environment environment(panorama);
  Model buried = test::sphereRelic();
  for (vec3& p : buried.meshes[0].positions) p.y -= 0.4f;  // the sphere from y = -0.28 to -0.04
  const LocalScene scene(test::plane(), buried, environment);
  const CameraModel view = test::camera();
  const cv::Mat background(view.height(), view.width(), CV_32FC3, cv::Scalar::all(0.5));
  const cv::Mat region = changeRegion(scene, view, background, {.exposure = kExposure});
  // Only the pixels whose rays point at the buried sphere (the footprint test does not look for
  // what hides it): within the sphere's angular radius and four pixels (the footprint's margin
  // and the dilation) of its centre.
  const RelicBounds& bounds = scene.relicBounds();
  const vec3 eye = view.ray({0.0f, 0.0f}).origin;
  const float distance = glm::length(bounds.centre - eye);
  const float pixel = glm::radians(50.0f) / static_cast<float>(view.height());
  const RelicBounds widened{bounds.centre,
                            distance * std::sin(std::asin(bounds.radius / distance) + 4.0f * pixel)};
  cv::Mat footprint(region.size(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x)
      if (widened.mayHit(view.ray({static_cast<float>(x), static_cast<float>(y)})))
        footprint.at<std::uint8_t>(y, x) = 255;
  EXPECT_EQ(cv::countNonZero(region & (footprint == 0)), 0);
  CompositeSettings s;
  s.spp = 64;
  const CompositeImage brute = renderComposite(scene, view, background, s);
  EXPECT_EQ(cv::norm(brute.radiance, background, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace holo::ar
