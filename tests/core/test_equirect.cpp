#include <gtest/gtest.h>
#include <random>

#include "holo/core/equirect.hpp"
#include "holo/core/image.hpp"

namespace holo {
namespace {

TEST(Equirect, DirectionRoundTrip) {
  std::mt19937 rng(3);
  std::normal_distribution<float> n;
  for (float yaw : {0.0f, 0.7f, -2.0f})
    for (int i = 0; i < 1000; ++i) {
      const vec3 d = glm::normalize(vec3(n(rng), n(rng), n(rng)));
      const vec3 back = equirect::uvToDirection(equirect::directionToUv(d, yaw), yaw);
      EXPECT_LT(glm::length(back - d), 1e-5f);
    }
}

TEST(Equirect, LeftStaysLeft) {
  // Centre column looks along -Z; +X appears to the right of the centre, +Y at the top.
  EXPECT_NEAR(equirect::directionToUv({0, 0, -1}).x, 0.5f, 1e-6f);
  EXPECT_NEAR(equirect::directionToUv({1, 0, 0}).x, 0.75f, 1e-6f);
  EXPECT_NEAR(equirect::directionToUv({-1, 0, 0}).x, 0.25f, 1e-6f);
  EXPECT_NEAR(equirect::directionToUv({0, 1, 0}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(equirect::directionToUv({0, -1, 0}).y, 1.0f, 1e-6f);
  // A positive yaw turns the panorama counter-clockwise seen from above: what was at -Z is now
  // found towards -X.
  EXPECT_NEAR(equirect::directionToUv({-1, 0, 0}, kPi / 2).x, 0.5f, 1e-5f);
}

TEST(Equirect, SolidAnglesSumToSphere) {
  double total = 0;
  for (int y = 0; y < 256; ++y) total += 512.0 * equirect::pixelSolidAngle(y, 512, 256);
  EXPECT_NEAR(total, 4.0 * kPi, 1e-3);
}

TEST(Equirect, SampleWrapsAndReturnsRgb) {
  cv::Mat pano(4, 8, CV_32FC3, cv::Scalar(0, 0, 0));
  for (int y = 0; y < 4; ++y) setRgb(pano, 7, y, {1, 2, 3});
  setRgb(pano, 0, 1, {1, 2, 3});
  setRgb(pano, 0, 2, {1, 2, 3});
  // u = 0 lies between the last and the first column: half of each.
  const vec3 c = equirect::sample(pano, equirect::uvToDirection({0.0f, 0.5f}));
  EXPECT_NEAR(c.r, 1.0f, 1e-5f);
  EXPECT_NEAR(c.b, 3.0f, 1e-5f);
}

}  // namespace
}  // namespace holo
