// Environment importance sampling: pdfs consistent with sample(), energy preserved exactly (the
// estimate radiance / pdf has zero variance in max(R,G,B)), finite on the hard sun, a single
// 1e6 pixel and an all-black panorama.
#include <gtest/gtest.h>

#include "holo/core/equirect.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/reference/sampler.hpp"
#include "holo/reflect/environment.hpp"
#include "shared_data.hpp"

namespace holo::reflect {
namespace {

using reference::SampleStream;

float maxChannel(const vec3& c) {
  return std::max({c.r, c.g, c.b});
}

// Checks every sample: finite, pdf() agrees, and max(RGB) / pdf equals the integral of
// max(RGB) over the sphere (the estimator of the power has zero variance).
void expectEnergyPreserving(const Environment& env, int samples) {
  double power = 0;  // integral of max(RGB)
  const cv::Mat& p = env.panorama();
  for (int y = 0; y < p.rows; ++y)
    for (int x = 0; x < p.cols; ++x)
      power += double(maxChannel(rgbAt(p, x, y))) * Environment::pixelSolidAngle(y, p.cols, p.rows);
  double estimate = 0;
  for (int i = 0; i < samples; ++i) {
    SampleStream s(11, 0, std::uint32_t(i));
    const EnvironmentSample e = env.sample(s.next2D());
    ASSERT_TRUE(e.pdf > 0 && std::isfinite(e.pdf));
    ASSERT_TRUE(isFinite(e.radiance) && isFinite(e.direction));
    EXPECT_NEAR(env.pdf(e.direction), e.pdf, 1e-3f * e.pdf);
    EXPECT_NEAR(glm::length(e.direction), 1.0f, 1e-5f);
    const double ratio = double(maxChannel(e.radiance)) / double(e.pdf);
    EXPECT_NEAR(ratio, power, 1e-3 * power);
    estimate += ratio;
  }
  EXPECT_NEAR(estimate / samples, power, 1e-3 * power);
}

TEST(Environment, UniformRadianceIsSampledUniformly) {
  const Environment env = Environment::uniform(vec3(1.0f));
  EXPECT_NEAR(env.integral().g, 4.0f * kPi, 1e-4f);
  for (int i = 0; i < 32; ++i) {
    SampleStream s(1, 2, std::uint32_t(i));
    EXPECT_NEAR(env.sample(s.next2D()).pdf, 1.0f / (4.0f * kPi), 1e-5f);
  }
}

TEST(Environment, SingleMillionPixelIsFiniteAndExact) {
  cv::Mat pano(64, 128, CV_32FC3, cv::Scalar::all(0));
  pano.at<cv::Vec3f>(20, 77) = cv::Vec3f(1e6f, 1e6f, 1e6f);
  const Environment env(pano);
  expectEnergyPreserving(env, 256);
  // Every sample lands in that pixel.
  SampleStream s(5, 0, 0);
  const vec2 uv = equirect::directionToUv(env.sample(s.next2D()).direction);
  EXPECT_EQ(int(uv.x * 128), 77);
  EXPECT_EQ(int(uv.y * 64), 20);
}

TEST(Environment, AllBlackSamplesNothing) {
  const Environment env = Environment::uniform(vec3(0.0f));
  EXPECT_TRUE(env.black());
  const EnvironmentSample e = env.sample({0.5f, 0.5f});
  EXPECT_EQ(e.pdf, 0.0f);
  EXPECT_EQ(env.pdf(vec3(0, 1, 0)), 0.0f);
  EXPECT_EQ(env.radiance(vec3(0, 1, 0)), vec3(0.0f));
}

TEST(Environment, NonFiniteAndNegativePixelsAreRepaired) {
  cv::Mat pano(8, 16, CV_32FC3, cv::Scalar::all(1));
  pano.at<cv::Vec3f>(1, 1) = cv::Vec3f(NAN, -3.0f, INFINITY);
  const Environment env(pano);
  EXPECT_EQ(env.repaired().total(), 3);
  EXPECT_TRUE(isFinite(env.integral()));
  expectEnergyPreserving(env, 64);
}

TEST(Environment, HardSunPanoramaIsEnergyPreserving) {
  HOLO_REQUIRE_SHARED_DATA("hdri/rooitou_park_1k.hdr");
  const Environment env(loadHdr(test::sharedData("hdri/rooitou_park_1k.hdr")).pixels);
  expectEnergyPreserving(env, 512);
}

TEST(Environment, YawRotatesLookups) {
  cv::Mat pano(16, 32, CV_32FC3, cv::Scalar::all(0));
  pano.at<cv::Vec3f>(8, 24) = cv::Vec3f(0, 0, 1);  // red, u = 0.78: towards +X
  const Environment plain(pano), turned(pano, 0.5f * kPi);
  const vec3 d = equirect::uvToDirection({24.5f / 32, 8.5f / 16});
  EXPECT_GT(plain.radiance(d).r, 0.5f);
  const vec3 rotated = equirect::uvToDirection({24.5f / 32, 8.5f / 16}, 0.5f * kPi);
  EXPECT_GT(turned.radiance(rotated).r, 0.5f);
  EXPECT_NE(plain.contentHash(), turned.contentHash());
}

}  // namespace
}  // namespace holo::reflect
