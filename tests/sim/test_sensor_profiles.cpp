#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

#include "holo/sim/depth_statistics.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/person_segmentation.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "shared_data.hpp"
#include "tum_walking.hpp"

namespace holo::sim {
namespace {

struct Truth {
  cv::Mat depth, cosine, radiance;
};

Truth wall(int width, int height, float z) {
  return {cv::Mat(height, width, CV_32FC1, cv::Scalar(z)), cv::Mat(height, width, CV_32FC1, cv::Scalar(1.0f)),
          cv::Mat(height, width, CV_32FC3, cv::Scalar(0.3f, 0.3f, 0.3f))};
}

// Only the geometry: no random, edge, dark or range holes, no noise.
SensorNoise geometryOnly(SensorProfile profile) {
  SensorNoise n = sensorProfile(profile);
  n.random_dropout = n.edge_dropout = n.dark_dropout = n.low_texture_dropout = 0.0f;
  n.flying_pixel = n.sigma_0 = n.k_z1 = n.k_z2 = 0.0f;
  n.range_fade_start = n.range_fade_end = 100.0f;
  n.edge_fattening_px = 0.0f;
  return n;
}

float focalPx(const CameraSettings& c) {
  return 0.5f * static_cast<float>(c.width) / std::tan(0.5f * c.hfov_deg * kPi / 180.0f);
}

// A person at 1 m in front of a wall at 3 m: the projector, baseline b to the camera's right,
// cannot light the strip of wall f b (1/1 - 1/3) pixels wide just left of the person; nothing
// right of a near object is shadowed.
TEST(SensorProfiles, TheProjectorShadowIsLeftOfNearObjectsAndAsWideAsTheBaselineSays) {
  const CameraSettings camera;  // 640 px over 110 degrees: f = 224 px
  const SensorNoise n = geometryOnly(SensorProfile::structured_light);
  Truth t = wall(camera.width, 40, 3.0f);
  t.depth(cv::Rect(300, 0, 40, 40)).setTo(1.0f);
  const SensorOutput out = applySensorNoise(n, camera, t.depth, t.cosine, t.radiance, 1, 2);
  const double expected = focalPx(camera) * n.baseline * (1.0 - 1.0 / 3.0);
  int holes_left = 0, holes_elsewhere = 0;
  for (int x = 0; x < camera.width; ++x) {
    const bool hole = out.depth.at<float>(20, x) == 0.0f;
    (x < 300 ? holes_left : holes_elsewhere) += hole;
  }
  EXPECT_NEAR(holes_left, expected, 1.0);
  EXPECT_EQ(holes_elsewhere, 0);
  for (int x = 300 - static_cast<int>(expected) + 1; x < 300; ++x)
    EXPECT_EQ(out.depth.at<float>(20, x), 0.0f) << x;
}

// Depth comes from quantised disparity: a slanted plane's measured depths take only the values
// f b / (k step), f and b the sensor's own.
TEST(SensorProfiles, StructuredLightDepthIsQuantisedInDisparity) {
  const SensorNoise n = geometryOnly(SensorProfile::structured_light);
  Truth t = wall(400, 8, 2.0f);
  for (int x = 0; x < 400; ++x) t.depth.col(x).setTo(1.8f + 0.001f * static_cast<float>(x));
  const SensorOutput out = applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 1, 2);
  const float fb = n.native_focal_px * n.baseline;
  std::set<float> values;
  for (int x = 0; x < 400; ++x) {
    const float d = out.depth.at<float>(4, x);
    ASSERT_GT(d, 0.0f);
    const float steps = fb / d / n.disparity_step_px;
    EXPECT_NEAR(steps, std::round(steps), 1e-3f);
    EXPECT_LE(std::abs(d - t.depth.at<float>(4, x)), 0.5f * d * d * n.disparity_step_px / fb * 1.01f);
    values.insert(d);
  }
  // 1.8-2.2 m spans f b / step * (1/1.8 - 1/2.2) disparity steps (70 for 580 px, 7.5 cm, 1/16 px).
  const double steps = fb / n.disparity_step_px * (1.0 / 1.8 - 1.0 / 2.2);
  EXPECT_GT(steps, 60.0);
  EXPECT_NEAR(static_cast<double>(values.size()), steps, 2.0);
}

// Holes come in patches that partly stay and partly change from frame to frame; the uniform
// profile's are mostly single pixels.
TEST(SensorProfiles, StructuredLightHolesArePatchesThatFlicker) {
  SensorNoise n = sensorProfile(SensorProfile::structured_light);
  n.dark_luminance = 1e6f;  // every pixel of the wall is "dark": dark_dropout is its hole rate
  n.dark_dropout = 0.3f;
  const Truth t = wall(320, 240, 2.0f);
  const SensorOutput a = applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 11, 99);
  const SensorOutput b = applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 12, 99);
  const SensorOutput a_again = applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 11, 99);
  EXPECT_EQ(cv::norm(a.depth, a_again.depth, cv::NORM_INF), 0.0);  // deterministic
  const cv::Mat holes_a = a.depth == 0.0f, holes_b = b.depth == 0.0f;
  const double both = cv::countNonZero(holes_a & holes_b), either = cv::countNonZero(holes_a | holes_b);
  const double fraction = cv::countNonZero(holes_a) / static_cast<double>(t.depth.total());
  EXPECT_GT(fraction, 0.05);
  EXPECT_LT(fraction, 0.5);
  // Partly static, partly flickering: the two frames share most but not all of their holes.
  EXPECT_GT(both / either, 0.3);
  EXPECT_LT(both / either, 0.9);
  const DepthStatistics patches = measureDepthStatistics(a.depth);
  EXPECT_LT(patches.hole_size_share[0] + patches.hole_size_share[1], 0.2);  // <= 10 px: few

  SensorNoise uniform;
  uniform.random_dropout = 0.1f;
  const DepthStatistics salt =
      measureDepthStatistics(applySensorNoise(uniform, {}, t.depth, t.cosine, t.radiance, 11).depth);
  EXPECT_GT(salt.hole_size_share[0] + salt.hole_size_share[1], 0.8);
}

// The structured-light profile reads the material under each pixel: a black surface, bare metal
// and a smooth surface seen head-on lose most of their depth; a mid-grey matte wall, brushed
// (rough) metal and the same gloss seen at 40 degrees keep nearly all of it.
TEST(SensorProfiles, StructuredLightLosesDarkMetalAndHighlights) {
  SensorNoise n = geometryOnly(SensorProfile::structured_light);
  const SensorNoise fitted = sensorProfile(SensorProfile::structured_light);
  n.dark_dropout = fitted.dark_dropout;
  const Truth t = wall(200, 150, 2.0f);
  const auto holes = [&](float albedo, float metallic, float roughness, float cosine) {
    const SurfaceMaps surface{cv::Mat(t.depth.size(), CV_32FC1, cv::Scalar(albedo)),
                              cv::Mat(t.depth.size(), CV_32FC1, cv::Scalar(metallic)),
                              cv::Mat(t.depth.size(), CV_32FC1, cv::Scalar(roughness))};
    const cv::Mat cosines(t.depth.size(), CV_32FC1, cv::Scalar(cosine));
    const SensorOutput out = applySensorNoise(n, {}, t.depth, cosines, t.radiance, 5, 6, surface);
    return 1.0 - cv::countNonZero(out.depth) / static_cast<double>(t.depth.total());
  };
  EXPECT_GT(holes(0.0f, 0.0f, 1.0f, 1.0f), 0.4);  // black: dark_dropout 0.7
  EXPECT_LT(holes(0.3f, 0.0f, 1.0f, 1.0f), 0.01);
  EXPECT_GT(holes(0.8f, 1.0f, 0.1f, 0.77f), 0.6);   // polished metal at 40 degrees
  EXPECT_LT(holes(0.8f, 1.0f, 1.0f, 0.77f), 0.01);  // fully rough metal scatters like paint
  EXPECT_GT(holes(0.5f, 0.0f, 0.0f, 1.0f), 0.6);    // varnish head-on: the highlight
  EXPECT_LT(holes(0.5f, 0.0f, 0.0f, 0.77f), 0.01);  // ... and 40 degrees off it
  EXPECT_LT(holes(0.5f, 0.0f, 0.6f, 1.0f), 0.01);   // satin: no highlight
  // Without material maps only the radiance stands in for the albedo: no metal, no highlight.
  EXPECT_LT(1.0 - cv::countNonZero(applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 5, 6).depth) /
                      static_cast<double>(t.depth.total()),
            0.01);
}

// Stereo: a textureless wall loses depth in patches, a textured one keeps it; the foreground
// spreads over the background beside an edge.
TEST(SensorProfiles, StereoLosesLowTextureAndFattensEdges) {
  SensorNoise n = geometryOnly(SensorProfile::stereo);
  n.low_texture_dropout = sensorProfile(SensorProfile::stereo).low_texture_dropout;
  Truth flat = wall(200, 100, 2.0f);
  Truth textured = wall(200, 100, 2.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 200; ++x)
      if (((x / 4) + (y / 4)) % 2) textured.radiance.at<cv::Vec3f>(y, x) = cv::Vec3f(0.05f, 0.05f, 0.05f);
  const auto holes = [&](const Truth& t) {
    const SensorOutput out = applySensorNoise(n, {}, t.depth, t.cosine, t.radiance, 3, 4);
    return 1.0 - cv::countNonZero(out.depth) / static_cast<double>(t.depth.total());
  };
  EXPECT_GT(holes(flat), 0.2);
  EXPECT_LT(holes(textured), 0.01);

  n.low_texture_dropout = 0.0f;
  n.edge_fattening_px = 3.0f;
  n.baseline = 0.0f;
  Truth step = wall(200, 20, 3.0f);
  step.depth(cv::Rect(100, 0, 100, 20)).setTo(1.0f);
  const SensorOutput out = applySensorNoise(n, {}, step.depth, step.cosine, step.radiance, 3, 4);
  for (int x = 90; x < 110; ++x) {
    const float d = out.depth.at<float>(10, x);
    EXPECT_FLOAT_EQ(d, x >= 97 ? 1.0f : 3.0f) << x;
  }
}

TEST(SensorProfiles, ScenesChooseAProfileByName) {
  const auto dir = test::scratchDir("sim_sensor_profile");
  const auto good = dir / "stereo.yaml";
  std::ofstream(good) << "base: room\nsensor: stereo\nnoise: {edge_fattening_px: 2}\n";
  const SceneDescription d = loadScene(good.string());
  EXPECT_EQ(d.noise.profile, SensorProfile::stereo);
  EXPECT_FLOAT_EQ(d.noise.edge_fattening_px, 2.0f);
  EXPECT_FLOAT_EQ(d.noise.low_texture_dropout, sensorProfile(SensorProfile::stereo).low_texture_dropout);
  // The fitted profile is every built-in scene's default, and a scene file's without `sensor:`.
  for (const auto& name : builtinSceneNames())
    EXPECT_EQ(loadScene(name).noise.profile, SensorProfile::structured_light) << name;
  const auto plain = dir / "plain.yaml";
  std::ofstream(plain) << "hall: room\n";
  EXPECT_EQ(loadScene(plain.string()).noise.profile, SensorProfile::structured_light);
  const auto bad = dir / "bad.yaml";
  std::ofstream(bad) << "sensor: lidar\n";
  try {
    loadScene(bad.string());
    FAIL() << "no error for an unknown profile";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), bad.string());
    EXPECT_EQ(e.field().rfind("sensor", 0), 0u) << e.field();
  }
  for (const auto& name : sensorProfileNames())
    EXPECT_STREQ(sensorProfileName(sensorProfileFromName(name)), name.c_str());
}

// The structured-light profile was fitted to the real Kinect frame with two people walking
// (TUM fr3/walking_xyz); the simulated museum's four cameras, pooled, must match its statistics:
// hole fraction within 25% relative, the share of holes beside a depth edge within 10 points,
// the share of hole pixels in patches over 100 px within 10 points, and the noise at 1, 2 and
// 4 m within 15%. The bars are those a reviewer would call "the same camera": a quarter of the
// holes is the frame-to-frame spread of a real sequence with people, 15% the repeatability of
// noise measured on different surfaces.
TEST(SensorProfiles, StructuredLightMatchesTheRealKinectFrameWithPeople) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum_walking/depth.png");
  const cv::Mat real_depth =
      loadDepthPng(test::sharedData("rgbd/tum_walking/depth.png").string(), test::kTumDepthUnitsPerMetre);
  const DepthStatistics real = measureDepthStatistics(
      real_depth, segmentPeople(real_depth, test::tumFr3Intrinsics(), test::tumWalkingPersonSeeds()));
  std::printf("real TUM walking_xyz:\n%s\n", describe(real).c_str());
  ASSERT_NEAR(real.hole_fraction, 0.294, 0.001);  // the file the README describes

  const Museum museum(loadScene("museum"));  // the default: structured-light
  // People found in the simulated frames as in the real one (segmentPeople, seeded from the true
  // foreground), so that holes on people are counted alike: holes on a person's own surface.
  std::vector<cv::Mat> depths, people;
  for (int camera = 0; camera < museum.cameraCount(); ++camera) {
    const SimulatedFrame f = museum.renderCamera(camera, 5);
    depths.push_back(f.frame.depth);
    const auto seeds = seedsFromMask(f.foreground, f.frame.depth, museum.camera(camera).intrinsics());
    people.push_back(seeds.empty() ? cv::Mat()
                                   : segmentPeople(f.frame.depth, museum.camera(camera).intrinsics(), seeds));
  }
  const DepthStatistics sim = measureDepthStatistics(depths, people);
  std::printf("simulated museum, structured-light, 4 cameras 640x360, frame 5:\n%s\n", describe(sim).c_str());

  EXPECT_NEAR(sim.hole_fraction / real.hole_fraction, 1.0, 0.25);
  EXPECT_NEAR(sim.edge_hole_share, real.edge_hole_share, 0.10);
  const auto large = [](const DepthStatistics& s) { return s.hole_size_share[3] + s.hole_size_share[4]; };
  EXPECT_NEAR(large(sim), large(real), 0.10);
  // People keep their depth where the room loses it (the real frame's black T-shirt included:
  // 0.03% holes on the people, 39% elsewhere): holes on the simulated people below 15% of those
  // elsewhere (measured 2.8% against 32.7%: the box visitors' limbs shadow their torsos, which a
  // real body's continuous surface does not; uniform: 1.8% against 3.5%), holes elsewhere within
  // 25% relative.
  EXPECT_LT(sim.person_hole_fraction, 0.15 * sim.other_hole_fraction);
  EXPECT_LT(real.person_hole_fraction, 0.15 * real.other_hole_fraction);
  EXPECT_NEAR(sim.other_hole_fraction / real.other_hole_fraction, 1.0, 0.25);
  for (std::size_t k = 0; k < kNoiseDepths.size(); ++k) {
    ASSERT_GT(real.noise[k], 0.0) << kNoiseDepths[k] << " m";
    ASSERT_GT(sim.noise[k], 0.0) << kNoiseDepths[k] << " m";
    EXPECT_NEAR(sim.noise[k] / real.noise[k], 1.0, 0.15) << "noise at " << kNoiseDepths[k] << " m";
  }

  // Today's uniform profile fails the same comparison: its holes are salt, not patches.
  SceneDescription salt_scene = loadScene("museum");
  salt_scene.noise = sensorProfile(SensorProfile::uniform);
  const Museum uniform(salt_scene);
  std::vector<cv::Mat> salt;
  for (int camera = 0; camera < uniform.cameraCount(); ++camera)
    salt.push_back(uniform.renderCamera(camera, 5).frame.depth);
  const DepthStatistics before = measureDepthStatistics(salt, {});
  std::printf("simulated museum, uniform:\n%s\n", describe(before).c_str());
  EXPECT_GT(std::abs(before.hole_fraction / real.hole_fraction - 1.0), 0.25);
}

}  // namespace
}  // namespace holo::sim
