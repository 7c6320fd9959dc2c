// The AR composite on a scene whose answer is known (ar_test_scene.hpp: a sphere on a plane
// under a small sun).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_test_scene.hpp"
#include "holo/ar/albedo_estimate.hpp"
#include "holo/ar/ar_view.hpp"
#include "holo/ar/change_filter.hpp"
#include "holo/ar/depth_surface.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/shapes.hpp"

namespace holo::ar {
namespace {

using test::camera;
using test::luminance;
using test::plane;
using test::samples;
using test::sphereRelic;
using test::sunnyPanorama;

struct Scene {
  cv::Mat panorama = sunnyPanorama();
  reflect::Environment environment{panorama};
  LocalScene local{plane(), sphereRelic(), environment};
  CameraModel view = camera();
};

// Mean of a - b over the real pixels where the relic darkens the truth by more than 10%.
struct ShadowComparison {
  double composite_change = 0, true_change = 0;
  int pixels = 0;
};

ShadowComparison compareInShadow(const cv::Mat& composite, const CompositeImage& truth, const cv::Mat& real) {
  ShadowComparison c;
  for (int y = 0; y < real.rows; ++y)
    for (int x = 0; x < real.cols; ++x) {
      if (truth.relic_coverage.at<float>(y, x) > 0.0f) continue;
      const float r = luminance(rgbAt(real, x, y)), t = luminance(rgbAt(truth.radiance, x, y));
      if (t > 0.9f * r) continue;
      c.true_change += t - r;
      c.composite_change += luminance(rgbAt(composite, x, y)) - r;
      ++c.pixels;
    }
  return c;
}

// The path tracer the truth and both renderers share, against a closed form: a Lambertian plane of
// albedo a under a uniform sky of radiance 1 (nothing below it) reflects exactly a.
TEST(LocalPathTracing, APlaneUnderAUniformSkyReflectsItsAlbedo) {
  cv::Mat sky(32, 64, CV_32FC3, cv::Scalar::all(0));
  sky.rowRange(0, 16).setTo(cv::Scalar::all(1.0));
  const reflect::Environment environment(sky);
  const LocalScene scene(plane(), Model{}, environment);
  const CameraModel view = camera();
  const CompositeImage image = renderLocalScene(scene, SceneContent::kReal, view, samples(64, 5));
  double sum = 0;
  int n = 0;
  for (int y = 0; y < image.radiance.rows; ++y)
    for (int x = 0; x < image.radiance.cols; ++x) {
      const Ray ray = view.ray({static_cast<float>(x), static_cast<float>(y)});
      const vec3 on_plane = ray.origin - (ray.origin.y / ray.direction.y) * ray.direction;
      if (ray.direction.y >= 0.0f || std::abs(on_plane.x) > 0.9f || std::abs(on_plane.z) > 0.9f) continue;
      sum += rgbAt(image.radiance, x, y).g;
      ++n;
    }
  ASSERT_GT(n, 500);
  EXPECT_NEAR(sum / n, test::kPlaneAlbedo, 0.005);
}

// The relic's glass against a closed form (a white furnace): clear glass under a uniform sky of
// radiance 1, nothing else in the scene, neither absorbs nor emits, so every path through it
// (reflected or refracted, totally internally reflected) brings exactly 1 back.
TEST(LocalPathTracing, ClearGlassUnderAUniformSkyNeitherLosesNorGainsLight) {
  const cv::Mat sky(32, 64, CV_32FC3, cv::Scalar::all(1.0));
  const reflect::Environment environment(sky);
  Model relic = sphereRelic();
  relic.materials[0].base_colour = vec3(1.0f);
  relic.materials[0].transmission = 1.0f;
  relic.materials[0].thickness = 0.1f;
  relic.materials[0].ior = 1.5f;
  const LocalScene glass(RealSurface{}, relic, environment);
  const CameraModel view = camera();
  const CompositeImage image = renderLocalScene(glass, SceneContent::kMixed, view, samples(4, 3));
  double low = 10, high = 0;
  int relic_pixels = 0;
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x)
      if (image.relic_coverage.at<float>(y, x) == 1.0f) {
        const float g = rgbAt(image.radiance, x, y).g;
        low = std::min<double>(low, g);
        high = std::max<double>(high, g);
        ++relic_pixels;
      }
  ASSERT_GT(relic_pixels, 30);
  EXPECT_NEAR(low, 1.0, 1e-3);
  EXPECT_NEAR(high, 1.0, 1e-3);
}

// A glass ball is a lens: seen level under a bright sky over a black ground, its upper half shows
// the ground and its lower half the sky (the image turned over), where the same ball opaque is
// lit from above.
TEST(LocalPathTracing, AGlassBallTurnsTheSkyOver) {
  cv::Mat sky(32, 64, CV_32FC3, cv::Scalar::all(0));
  sky.rowRange(0, 16).setTo(cv::Scalar::all(1.0));
  const reflect::Environment environment(sky);
  const CameraModel level(Intrinsics::fromFov(48, 32, glm::radians(30.0f), glm::radians(20.0f)),
                          lookAtCameraToWorld({0.0f, 0.12f, 1.0f}, {0.0f, 0.12f, 0.0f}));
  // Mean radiance of the ball's upper and lower halves in the image.
  const auto halves = [&](bool transmissive) {
    Model relic = sphereRelic();
    relic.materials[0].base_colour = vec3(1.0f);
    relic.materials[0].transmission = transmissive ? 1.0f : 0.0f;
    relic.materials[0].thickness = 0.1f;
    const LocalScene scene(RealSurface{}, relic, environment);
    const CompositeImage image = renderLocalScene(scene, SceneContent::kMixed, level, samples(16, 3));
    const cv::Mat on_relic = image.relic_coverage == 1.0f;
    const int mid = level.height() / 2;
    const cv::Scalar upper = cv::mean(image.radiance.rowRange(0, mid), on_relic.rowRange(0, mid));
    const cv::Scalar lower =
        cv::mean(image.radiance.rowRange(mid, level.height()), on_relic.rowRange(mid, level.height()));
    return std::pair<double, double>(upper[1], lower[1]);
  };
  const auto [glass_upper, glass_lower] = halves(true);
  const auto [opaque_upper, opaque_lower] = halves(false);
  EXPECT_LT(glass_upper, 0.5 * glass_lower) << "glass: upper " << glass_upper << ", lower " << glass_lower;
  EXPECT_GT(opaque_upper, 2.0 * opaque_lower)
      << "opaque: upper " << opaque_upper << ", lower " << opaque_lower;
}

TEST(ArComposite, DeltaPathTracingOnExactInputsGivesTheMixedScene) {
  const Scene s;
  const cv::Mat real = renderLocalScene(s.local, SceneContent::kReal, s.view, samples(256, 7)).radiance;
  const CompositeImage truth = renderLocalScene(s.local, SceneContent::kMixed, s.view, samples(256, 7));
  const CompositeImage delta =
      renderComposite(s.local, s.view, real, samples(256, 3, DifferentialMethod::kDeltaPathTracing));
  const ShadowComparison c = compareInShadow(delta.radiance, truth, real);
  ASSERT_GT(c.pixels, 20) << "the sphere casts a shadow in view";
  ASSERT_LT(c.true_change, 0.0);
  EXPECT_NEAR(c.composite_change / c.true_change, 1.0, 0.05);
  EXPECT_GT(cv::countNonZero(delta.relic_coverage > 0.0f), 50);
}

TEST(ArComposite, TwoPassDifferentialRenderingConvergesToTheSameImage) {
  const Scene s;
  const cv::Mat real = renderLocalScene(s.local, SceneContent::kReal, s.view, samples(256, 7)).radiance;
  const CompositeImage truth = renderLocalScene(s.local, SceneContent::kMixed, s.view, samples(256, 7));
  const CompositeImage two_pass =
      renderComposite(s.local, s.view, real, samples(256, 3, DifferentialMethod::kTwoPass));
  const ShadowComparison c = compareInShadow(two_pass.radiance, truth, real);
  EXPECT_NEAR(c.composite_change / c.true_change, 1.0, 0.1);
}

// A two-pass renderer given 1-spp passes until it has cast at least `rays` rays.
// The camera's depth of the scene's real surface (camera-frame z; 0 where it sees nothing).
cv::Mat depthOfReal(const LocalScene& scene, const CameraModel& view) {
  cv::Mat depth(view.height(), view.width(), CV_32FC1, cv::Scalar(0));
  const vec3 forward = glm::normalize(vec3(view.T_world_camera()[2]));
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const Ray ray = view.ray({static_cast<float>(x), static_cast<float>(y)});
      const RayHit hit = scene.intersect(SceneContent::kReal, ray);
      if (hit.hit()) depth.at<float>(y, x) = hit.t * glm::dot(ray.direction, forward);
    }
  return depth;
}

// Mean luminance and RMSE (linear) against the truth over the pixels every sample of both saw the relic.
struct RelicScore {
  double mean = 0, truth_mean = 0, rmse = 0;
  int pixels = 0;
};

RelicScore scoreRelic(const CompositeImage& image, const CompositeImage& truth) {
  RelicScore r;
  for (int y = 0; y < truth.radiance.rows; ++y)
    for (int x = 0; x < truth.radiance.cols; ++x) {
      if (truth.relic_coverage.at<float>(y, x) < 1.0f || image.relic_coverage.at<float>(y, x) < 1.0f)
        continue;
      const float a = luminance(rgbAt(image.radiance, x, y)), t = luminance(rgbAt(truth.radiance, x, y));
      r.mean += a;
      r.truth_mean += t;
      r.rmse += (a - t) * (a - t);
      ++r.pixels;
    }
  if (r.pixels > 0) {
    r.mean /= r.pixels;
    r.truth_mean /= r.pixels;
    r.rmse = std::sqrt(r.rmse / r.pixels);
  }
  return r;
}

// The relic reflects the real plane as the camera saw it: with the camera's depth, a relic path
// that meets the plane where the camera sees it takes the camera's radiance there (plus the relic's
// change), so a local scene whose albedo is wrong (0.15 for 0.5) no longer darkens the plane a
// mirror sphere shows; on the right albedo the measured radiance agrees with the traced. Under a
// sky without a sun (the sun's glint in the mirror would dominate every figure).
TEST(ArComposite, TheRelicReflectsTheRealSurfaceAsTheCameraSawIt) {
  Scene s;
  s.panorama.setTo(cv::Scalar::all(1.0));  // a uniform sky: smooth light, no glint to dominate
  s.panorama.rowRange(s.panorama.rows / 2, s.panorama.rows).setTo(cv::Scalar::all(0.1));
  s.environment = reflect::Environment(s.panorama);
  Model mirror = sphereRelic();
  mirror.materials[0].base_colour = vec3(0.9f);
  mirror.materials[0].metallic = 1.0f;
  mirror.materials[0].roughness = 0.05f;
  const LocalScene exact(plane(), mirror, s.environment);
  const cv::Mat real = renderLocalScene(exact, SceneContent::kReal, s.view, samples(256, 7)).radiance;
  const CompositeImage truth = renderLocalScene(exact, SceneContent::kMixed, s.view, samples(256, 7));
  const cv::Mat depth = depthOfReal(exact, s.view);
  RealSurface dark = plane();
  std::fill(dark.albedo.begin(), dark.albedo.end(), vec3(0.15f));
  const LocalScene wrong(std::move(dark), mirror, s.environment);
  const CompositeSettings delta = samples(64, 3, DifferentialMethod::kDeltaPathTracing);
  const RelicScore traced = scoreRelic(renderComposite(wrong, s.view, real, delta), truth);
  const RelicScore measured =
      scoreRelic(renderComposite(wrong, s.view, real, delta, cv::Mat(), depth), truth);
  ASSERT_GT(traced.pixels, 30);
  EXPECT_LT(traced.mean, 0.9 * traced.truth_mean) << "the wrong albedo darkens the plane the sphere mirrors";
  EXPECT_LT(measured.rmse, 0.5 * traced.rmse) << traced.rmse << " -> " << measured.rmse;
  EXPECT_NEAR(measured.mean / measured.truth_mean, 1.0, 0.05) << traced.mean / traced.truth_mean;
  const RelicScore right = scoreRelic(renderComposite(exact, s.view, real, delta, cv::Mat(), depth), truth);
  EXPECT_NEAR(right.mean / right.truth_mean, 1.0, 0.05);
  std::cout << "relic pixels " << traced.pixels << ": mean / truth traced " << traced.mean / traced.truth_mean
            << ", measured " << measured.mean / measured.truth_mean << ", right albedo measured "
            << right.mean / right.truth_mean << "; RMSE traced " << traced.rmse << ", measured "
            << measured.rmse << "\n";
}

cv::Mat twoPassAtRays(const Scene& s, const cv::Mat& real, DifferentialMethod method, std::int64_t rays) {
  CompositeSettings pass = samples(1, 11, method);
  cv::Mat sum(real.size(), CV_32FC3, cv::Scalar::all(0));
  for (std::int64_t cast = 0; cast < rays; ++pass.first_sample) {
    const CompositeImage image = renderComposite(s.local, s.view, real, pass);
    sum += image.radiance;
    cast += image.rays;
  }
  return sum / static_cast<double>(pass.first_sample);
}

// Over the plane's pixels that see no relic (the sky beyond it is the camera's image in every
// method): the summed error against the truth, and the pixels left exactly as the camera saw them.
struct PlaneScore {
  double error = 0;
  int pixels = 0, untouched = 0;
};

PlaneScore planeScore(const Scene& s, const cv::Mat& image, const CompositeImage& truth,
                      const cv::Mat& real) {
  PlaneScore score;
  for (int y = 0; y < real.rows; ++y)
    for (int x = 0; x < real.cols; ++x) {
      if (truth.relic_coverage.at<float>(y, x) > 0.0f) continue;
      if (!s.local.intersect(SceneContent::kReal, s.view.ray({static_cast<float>(x), static_cast<float>(y)}))
               .hit())
        continue;
      score.error += glm::length(rgbAt(image, x, y) - rgbAt(truth.radiance, x, y));
      ++score.pixels;
      score.untouched += rgbAt(image, x, y) == rgbAt(real, x, y) ? 1 : 0;
    }
  return score;
}

// The scene's truth and camera image, delta path tracing at 4 spp and the two-pass renderer with
// independent samples at its count of rays, each scored over the plane.
struct EqualRays {
  Scene s;
  cv::Mat real = renderLocalScene(s.local, SceneContent::kReal, s.view, samples(256, 7)).radiance;
  CompositeImage truth = renderLocalScene(s.local, SceneContent::kMixed, s.view, samples(256, 7));
  CompositeImage delta =
      renderComposite(s.local, s.view, real, samples(4, 11, DifferentialMethod::kDeltaPathTracing));
  PlaneScore d = planeScore(s, delta.radiance, truth, real);
  PlaneScore independent =
      planeScore(s, twoPassAtRays(s, real, DifferentialMethod::kTwoPass, delta.rays), truth, real);
};

// Xu et al.'s point: where the relic changes nothing, delta path tracing adds exactly nothing,
// and where it does, its error at the same count of rays is far below two renders' difference.
TEST(ArComposite, DeltaPathTracingBeatsTwoPassAtEqualRays) {
  const EqualRays r;
  EXPECT_GT(r.independent.error, 2.0 * r.d.error)
      << "two-pass " << r.independent.error << ", delta " << r.d.error;
  EXPECT_GT(r.d.untouched, r.d.pixels / 3);
  EXPECT_LT(r.independent.untouched, r.independent.pixels / 10);
}

// The two-pass renderer with shared samples (the strongest plain differential renderer): a plane
// pixel sample whose mixed-scene path never meets the relic draws the same path in the real scene
// and adds exactly nothing, as delta path tracing does, and at equal rays its error over the plane
// is below 0.3x the two-pass renderer's with independent samples (measured 0.09; still above delta path
// tracing's, 61 against 51: it traces both whole paths where delta path tracing traces the change).
TEST(ArComposite, TwoPassWithSharedSamplesCancelsWhereTheRelicDoesNotReach) {
  const EqualRays r;
  const PlaneScore shared =
      planeScore(r.s, twoPassAtRays(r.s, r.real, DifferentialMethod::kTwoPassSharedSamples, r.delta.rays),
                 r.truth, r.real);
  EXPECT_LT(shared.error, 0.3 * r.independent.error)
      << "shared " << shared.error << ", independent " << r.independent.error;
  EXPECT_GT(shared.untouched, shared.pixels / 3);
  EXPECT_GT(shared.error, r.d.error) << "shared " << shared.error << ", delta " << r.d.error;
}

// Delta path tracing's change on the real pixels is quiet where the relic's own pixels (the mixed
// scene path traced) are noisy: relic_spp_factor gives the pixels where the relic is seen more
// samples. Their error against the truth falls (4x the samples: about half), the rays counted rise,
// and every pixel away from the relic is left exactly as it was.
TEST(ArComposite, TheRelicsPixelsTakeMoreSamplesAndTheOthersAreUnchanged) {
  Scene s;
  const cv::Mat real = renderLocalScene(s.local, SceneContent::kReal, s.view, samples(256, 7)).radiance;
  const CompositeImage truth = renderLocalScene(s.local, SceneContent::kMixed, s.view, samples(256, 7));
  const CompositeImage uniform = renderComposite(s.local, s.view, real, samples(4, 11));
  CompositeSettings split_settings = samples(4, 11);
  split_settings.relic_spp_factor = 4;
  const CompositeImage split = renderComposite(s.local, s.view, real, split_settings);
  cv::Mat near_relic;
  cv::dilate(truth.relic_coverage > 0.0f, near_relic, cv::Mat::ones(5, 5, CV_8UC1));
  double uniform_error = 0, split_error = 0;
  int relic_pixels = 0, changed_away = 0;
  for (int y = 0; y < real.rows; ++y)
    for (int x = 0; x < real.cols; ++x) {
      const float t = luminance(rgbAt(truth.radiance, x, y));
      if (truth.relic_coverage.at<float>(y, x) == 1.0f) {
        uniform_error += std::pow(luminance(rgbAt(uniform.radiance, x, y)) - t, 2.0f);
        split_error += std::pow(luminance(rgbAt(split.radiance, x, y)) - t, 2.0f);
        ++relic_pixels;
      } else if (!near_relic.at<std::uint8_t>(y, x) &&
                 rgbAt(split.radiance, x, y) != rgbAt(uniform.radiance, x, y)) {
        ++changed_away;
      }
    }
  ASSERT_GT(relic_pixels, 30);
  std::cout << "relic pixels' squared error: split " << split_error << ", uniform " << uniform_error << "\n";
  EXPECT_LT(split_error, 0.6 * uniform_error) << "split " << split_error << ", uniform " << uniform_error;
  EXPECT_EQ(changed_away, 0);
  EXPECT_GT(split.rays, uniform.rays + 3 * 4 * relic_pixels);
  split_settings.relic_spp_factor = 0;
  EXPECT_THROW(renderComposite(s.local, s.view, real, split_settings), InputError);
}

TEST(DepthSurface, IsTheSeenPlaneAndDropsSilhouettesAndFarPoints) {
  const CameraModel view = camera(40, 30);
  cv::Mat depth(30, 40, CV_32FC1);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      // The plane y = 0 where the ray meets it, a far wall (beyond the radius) elsewhere.
      const Ray ray = view.ray({static_cast<float>(x), static_cast<float>(y)});
      const vec3 forward = vec3(view.T_world_camera()[2]);
      const float t = ray.direction.y < -1e-3f ? -ray.origin.y / ray.direction.y : 100.0f;
      depth.at<float>(y, x) = std::min(t, 100.0f) * glm::dot(ray.direction, glm::normalize(forward));
    }
  DepthSurfaceSettings settings;
  settings.radius = 1.5f;
  const DepthSurface surface = depthSurface(depth, view, settings, "camera 0");
  ASSERT_GT(surface.mesh.triangles.size(), 100u);
  for (std::size_t i = 0; i < surface.mesh.positions.size(); ++i) {
    EXPECT_NEAR(surface.mesh.positions[i].y, 0.0f, 1e-4f);
    EXPECT_LE(glm::length(surface.mesh.positions[i]), 1.5f + 1e-4f);
    EXPECT_GT(surface.mesh.normals[i].y, 0.999f);
  }
  // The albedo of a plane lit by a uniform sky of 1 seen at radiance 0.25: pi * 0.25 / pi.
  cv::Mat radiance(30, 40, CV_32FC3, cv::Scalar::all(0.25));
  const reflect::Environment sky = reflect::Environment::uniform(vec3(1.0f));
  const std::vector<vec3> albedo = estimateAlbedo(surface, radiance, reflect::IrradianceSH(sky));
  for (const vec3& a : albedo) EXPECT_NEAR(a.g, 0.25f, 0.01f);
}

TEST(ChangeFilter, SmoothsTheChangeButNotAcrossADepthEdgeOrOverTheRelic) {
  const int w = 24, h = 12;
  cv::Mat background(h, w, CV_32FC3, cv::Scalar::all(1.0));
  cv::Mat composite(h, w, CV_32FC3), depth(h, w, CV_32FC1), coverage(h, w, CV_32FC1, cv::Scalar(0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool shadow = x < w / 2;  // a shadow on the near surface, none on the far one
      const float noise = ((x + y) % 2 == 0 ? 0.2f : -0.2f);
      setRgb(composite, x, y, vec3(1.0f + (shadow ? -0.5f : 0.0f) + noise));
      depth.at<float>(y, x) = shadow ? 1.0f : 2.0f;
    }
  coverage.at<float>(5, 3) = 1.0f;
  setRgb(composite, 3, 5, vec3(7.0f));
  const cv::Mat filtered = filterChange(composite, background, coverage, depth, {});
  EXPECT_EQ(rgbAt(filtered, 3, 5), vec3(7.0f));
  for (int y = 2; y < h - 2; ++y) {
    EXPECT_NEAR(rgbAt(filtered, w / 2 - 1, y).g, 0.5f, 0.06f) << "the near side of the edge, row " << y;
    EXPECT_NEAR(rgbAt(filtered, w / 2, y).g, 1.0f, 0.06f) << "the far side of the edge, row " << y;
    EXPECT_NEAR(rgbAt(filtered, 8, y).g, 0.5f, 0.06f);
  }
  ChangeFilterSettings off;
  off.enabled = false;
  EXPECT_EQ(cv::norm(filterChange(composite, background, coverage, depth, off), composite, cv::NORM_INF),
            0.0);
}

RgbdFrame goodFrame(const CameraModel& view) {
  RgbdFrame frame;
  frame.colour = cv::Mat(view.height(), view.width(), CV_8UC3, cv::Scalar::all(100));
  frame.depth = cv::Mat(view.height(), view.width(), CV_32FC1, cv::Scalar(1.0f));
  return frame;
}

std::string refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A depth with one valid pixel, or none near the relic, leaves no real surface: the composite is
// the relic over the camera's image, finite.
TEST(ArView, AlmostNoDepthGivesTheRelicOverTheImage) {
  const CameraModel view = camera();
  const Model relic = sphereRelic();
  const cv::Mat panorama = sunnyPanorama();
  ArViewSettings settings;
  settings.composite.spp = 2;
  for (const float far : {0.0f, 50.0f}) {
    RgbdFrame frame = goodFrame(view);
    frame.depth.setTo(far);
    frame.depth.at<float>(3, 3) = std::numeric_limits<float>::quiet_NaN();
    frame.depth.at<float>(4, 4) = 1.0f;
    const ArView out = renderArView(0, view, frame, relic, panorama, settings);
    EXPECT_GT(out.relic_pixels, 50);
    EXPECT_EQ(cv::checkRange(out.radiance), true);
    EXPECT_EQ(out.image.at<cv::Vec3b>(0, 0), cv::Vec3b(100, 100, 100))
        << "far from the relic: the camera's pixel";
  }
}

TEST(ArCamera, AMissingUncalibratedOrDepthlessCameraIsRefusedByName) {
  const CameraModel view = camera();
  EXPECT_EQ(refusal([&] { requireArCameraIndex(2, 4); }), "");
  EXPECT_EQ(refusal([&] { requireArCameraInputs(2, view, goodFrame(view)); }), "");

  const std::string missing = refusal([&] { requireArCameraIndex(4, 4); });
  EXPECT_NE(missing.find("camera 4"), std::string::npos) << missing;
  EXPECT_NE(missing.find("0 to 3"), std::string::npos) << missing;
  EXPECT_NE(refusal([&] { requireArCameraIndex(-1, 4); }).find("camera -1"), std::string::npos);

  const std::string uncalibrated = refusal([&] { requireArCameraInputs(1, CameraModel{}, goodFrame(view)); });
  EXPECT_NE(uncalibrated.find("camera 1"), std::string::npos) << uncalibrated;
  EXPECT_NE(uncalibrated.find("calibrat"), std::string::npos) << uncalibrated;
  CameraModel bent = view;
  mat4 pose = view.T_world_camera();
  pose[0] *= 2.0f;  // not a rotation
  bent.setPose(pose);
  EXPECT_NE(refusal([&] { requireArCameraInputs(1, bent, goodFrame(view)); }).find("T_world_camera"),
            std::string::npos);

  RgbdFrame no_depth = goodFrame(view);
  no_depth.depth = cv::Mat();
  const std::string depthless = refusal([&] { requireArCameraInputs(3, view, no_depth); });
  EXPECT_NE(depthless.find("camera 3"), std::string::npos) << depthless;
  EXPECT_NE(depthless.find("depth"), std::string::npos) << depthless;
  RgbdFrame invalid_depth = goodFrame(view);
  invalid_depth.depth.setTo(0.0f);
  EXPECT_NE(refusal([&] { requireArCameraInputs(3, view, invalid_depth); }).find("valid depth"),
            std::string::npos);
}

}  // namespace
}  // namespace holo::ar
