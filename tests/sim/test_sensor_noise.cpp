#include <gtest/gtest.h>
#include <cmath>

#include "holo/core/image.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/sensor_noise.hpp"

namespace holo::sim {
namespace {

struct Truth {
  cv::Mat depth, cosine, radiance;
};

Truth flatWall(float z, int size = 96) {
  return {cv::Mat(size, size, CV_32FC1, cv::Scalar(z)), cv::Mat(size, size, CV_32FC1, cv::Scalar(1.0f)),
          cv::Mat(size, size, CV_32FC3, cv::Scalar(0.2f, 0.2f, 0.2f))};
}

// The measured standard deviation of the depth noise on a fronto-parallel wall at 1, 2 and 4 m
// matches sigma(z) = sigma_0 + k_z2 z^2 (the bar: within 15%).
TEST(SensorNoise, DepthSigmaMatchesTheModelAt1_2_4m) {
  SensorNoise noise;
  const CameraSettings camera;
  for (float z : {1.0f, 2.0f, 4.0f}) {
    const Truth t = flatWall(z);
    const SensorOutput out =
        applySensorNoise(noise, camera, t.depth, t.cosine, t.radiance, 11 + static_cast<std::uint64_t>(z));
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int y = 1; y < t.depth.rows - 1; ++y)
      for (int x = 1; x < t.depth.cols - 1; ++x) {
        const float d = out.depth.at<float>(y, x);
        if (d <= 0) continue;
        sum += d - z;
        sum2 += (d - z) * (d - z);
        ++n;
      }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    const double expected = depthSigma(noise, z);
    std::printf("z = %.0f m: measured sigma %.5f m, model %.5f m (ratio %.3f, %d pixels)\n", z, sd, expected,
                sd / expected, n);
    EXPECT_NEAR(sd / expected, 1.0, 0.15) << "at " << z << " m";
    EXPECT_NEAR(mean, 0.0, 4.0 * expected / std::sqrt(n));  // unbiased
    // Random dropouts: about 1% of the pixels.
    const double dropped = 1.0 - double(cv::countNonZero(out.depth)) / double(t.depth.total());
    EXPECT_NEAR(dropped, noise.random_dropout, 0.006);
  }
}

TEST(SensorNoise, GrazingAnglesDropOut) {
  SensorNoise noise;
  Truth t = flatWall(2.0f, 32);
  t.cosine.setTo(std::cos((noise.grazing_dropout_deg + 1.0f) * kPi / 180.0f));
  EXPECT_EQ(cv::countNonZero(applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 1).depth), 0);
  t.cosine.setTo(std::cos((noise.grazing_dropout_deg - 1.0f) * kPi / 180.0f));
  EXPECT_GT(cv::countNonZero(applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 1).depth), 900);
}

// A step from 1 m to 3 m: edge pixels drop out at the configured rate and some of the rest fly
// between the two sides; pixels away from the edge never take such a depth.
TEST(SensorNoise, DepthEdgesDropAndFly) {
  SensorNoise noise;
  noise.random_dropout = 0.0f;
  Truth t = flatWall(3.0f, 200);
  t.depth(cv::Rect(0, 0, 100, 200)).setTo(1.0f);
  const SensorOutput out = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 5);
  int edge = 0, edge_dropped = 0, flying = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) {
      const float d = out.depth.at<float>(y, x);
      const bool mixed = d > 1.2f && d < 2.7f;
      if (x == 99 || x == 100) {
        ASSERT_TRUE(isDepthEdge(t.depth, x, y));
        ++edge;
        edge_dropped += d == 0.0f;
        flying += mixed;
      } else {
        ASSERT_FALSE(isDepthEdge(t.depth, x, y));
        EXPECT_FALSE(mixed) << x << "," << y;
        EXPECT_GT(d, 0.0f);
      }
    }
  EXPECT_NEAR(double(edge_dropped) / edge, noise.edge_dropout, 0.08);
  EXPECT_NEAR(double(flying) / (edge - edge_dropped), noise.flying_pixel, 0.1);
}

TEST(SensorNoise, ColourNoiseHasTheConfiguredSigma) {
  SensorNoise noise;
  noise.colour_sigma = 3.0f;
  const Truth t = flatWall(2.0f, 128);
  const SensorOutput out = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 3);
  cv::Scalar mean, sd;
  cv::meanStdDev(out.colour.reshape(1), mean, sd);
  EXPECT_NEAR(sd[0], 3.0, 0.3);                           // rounding to 8 bits adds ~0.29^2 in variance
  EXPECT_NEAR(mean[0], 255.0 * linearToSrgb(0.2f), 0.1);  // sRGB of the radiance, unbiased
  noise.enabled = false;
  const SensorOutput clean = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 3);
  EXPECT_EQ(cv::norm(clean.depth, t.depth, cv::NORM_INF), 0.0);  // disabled: the truth itself
}

TEST(SensorNoise, NonFiniteInputStaysFiniteAndInRange) {
  SensorNoise noise;
  CameraSettings camera;
  Truth t = flatWall(2.0f, 16);
  t.depth.at<float>(1, 1) = std::numeric_limits<float>::quiet_NaN();
  t.depth.at<float>(2, 2) = std::numeric_limits<float>::infinity();
  t.depth.at<float>(3, 3) = -1.0f;
  t.radiance.at<cv::Vec3f>(4, 4) = cv::Vec3f(std::numeric_limits<float>::quiet_NaN(), -5.0f, 1e30f);
  t.cosine.at<float>(5, 5) = std::numeric_limits<float>::quiet_NaN();
  const SensorOutput out = applySensorNoise(noise, camera, t.depth, t.cosine, t.radiance, 9);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const float d = out.depth.at<float>(y, x);
      ASSERT_TRUE(d == 0.0f || (d >= camera.min_range && d <= camera.max_range)) << d;
    }
}

TEST(SensorNoise, SameSeedSameNoiseDifferentSeedDifferent) {
  const Truth t = flatWall(2.0f, 64);
  const SensorNoise noise;
  const auto a = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 1);
  const auto b = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 1);
  const auto c = applySensorNoise(noise, {}, t.depth, t.cosine, t.radiance, 2);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.colour, b.colour, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.depth, c.depth, cv::NORM_INF), 0.0);
}

// End to end: in a rendered museum frame, away from edges, (measured - true) / sigma(true) has
// unit standard deviation.
TEST(SensorNoise, MuseumFramesFollowTheModel) {
  SceneDescription d = loadScene("museum");
  d.noise = sensorProfile(SensorProfile::uniform);  // the Gaussian model without quantisation
  d.camera.width = 160;
  d.camera.height = 90;
  const Museum m(d);
  double sum2 = 0;
  int n = 0;
  for (int cam = 0; cam < 4; ++cam) {
    const SimulatedFrame f = m.renderCamera(cam, 4);
    for (int y = 0; y < f.true_depth.rows; ++y)
      for (int x = 0; x < f.true_depth.cols; ++x) {
        const float z = f.true_depth.at<float>(y, x), measured = f.frame.depth.at<float>(y, x);
        if (z <= 0 || measured <= 0 || isDepthEdge(f.true_depth, x, y)) continue;
        const double r = (measured - z) / depthSigma(d.noise, z);
        sum2 += r * r;
        ++n;
      }
  }
  ASSERT_GT(n, 10000);
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.0, 0.05);
}

}  // namespace
}  // namespace holo::sim
