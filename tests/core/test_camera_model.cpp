#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <random>

#include "holo/core/camera_model.hpp"

namespace holo {
namespace {

CameraModel distortedCamera() {
  Intrinsics K = Intrinsics::fromFov(640, 360, glm::radians(110.0f), glm::radians(70.0f));
  // Mild barrel distortion, as a wide-angle depth camera has; strong k3 makes the model fold
  // over inside the image, where no undistortion can be unique.
  K.distortion = {-0.04f, 0.008f, 0.0008f, -0.0006f, -0.0005f};
  return CameraModel(K, lookAtCameraToWorld({1.2f, 0.4f, 0.9f}, {0, 0.3f, 0}));
}

TEST(CameraModel, ProjectMatchesOpenCv) {
  const CameraModel cam = distortedCamera();
  const auto& K = cam.intrinsics();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> xy(-0.9f, 0.9f), z(0.3f, 8.0f);
  std::vector<cv::Point3f> points;
  for (int i = 0; i < 200; ++i) {
    const float depth = z(rng);
    points.emplace_back(xy(rng) * depth, xy(rng) * depth * 0.6f, depth);
  }
  std::vector<cv::Point2f> expected;
  cv::projectPoints(
      points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Matx33d(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1),
      cv::Vec<double, 5>(K.distortion[0], K.distortion[1], K.distortion[2], K.distortion[3], K.distortion[4]),
      expected);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto px = cam.projectCamera({points[i].x, points[i].y, points[i].z});
    ASSERT_TRUE(px.has_value());
    EXPECT_NEAR(px->x, expected[i].x, 1e-2f);
    EXPECT_NEAR(px->y, expected[i].y, 1e-2f);
  }
}

TEST(CameraModel, UnprojectProjectRoundTripWithDistortion) {
  const CameraModel cam = distortedCamera();
  for (int v = 0; v < cam.height(); v += 17)
    for (int u = 0; u < cam.width(); u += 23) {
      const vec2 pixel(float(u) + 0.25f, float(v) + 0.75f);
      const vec3 world = cam.unproject(pixel, 2.5f);
      float depth = 0;
      const auto back = cam.project(world, &depth);
      ASSERT_TRUE(back.has_value());
      EXPECT_NEAR(depth, 2.5f, 1e-4f);
      EXPECT_NEAR(back->x, pixel.x, 2e-3f) << "at pixel " << u << "," << v;
      EXPECT_NEAR(back->y, pixel.y, 2e-3f) << "at pixel " << u << "," << v;
    }
}

TEST(CameraModel, RayPassesThroughUnprojectedPoint) {
  const CameraModel cam = distortedCamera();
  const vec2 pixel(100.5f, 300.25f);
  const Ray ray = cam.ray(pixel);
  const vec3 p = cam.unproject(pixel, 3.0f);
  const vec3 to_p = glm::normalize(p - ray.origin);
  EXPECT_GT(glm::dot(to_p, ray.direction), 1.0f - 1e-6f);
  EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
}

TEST(CameraModel, BehindCameraDoesNotProject) {
  const CameraModel cam = distortedCamera();
  EXPECT_FALSE(cam.projectCamera({0.1f, 0.1f, -1.0f}).has_value());
  EXPECT_FALSE(cam.projectCamera({0.1f, 0.1f, 0.0f}).has_value());
}

TEST(CameraModel, LookAtFollowsOpenCvAxes) {
  const mat4 T = lookAtCameraToWorld({0, 1, 3}, {0, 1, 0});
  EXPECT_NEAR(glm::dot(vec3(T[2]), vec3(0, 0, -1)), 1.0f, 1e-6f);  // +Z looks at the target
  EXPECT_NEAR(glm::dot(vec3(T[1]), vec3(0, -1, 0)), 1.0f, 1e-6f);  // +Y is down
  EXPECT_NEAR(glm::dot(vec3(T[0]), vec3(1, 0, 0)), 1.0f, 1e-6f);   // right-handed: +X right
  const mat4 Tinv = rigidInverse(T);
  const mat4 I = T * Tinv;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(I[c][r], c == r ? 1.0f : 0.0f, 1e-6f);
}

TEST(CameraModel, DirectionTableMatchesSingleUnproject) {
  const CameraModel cam = distortedCamera();
  const auto table = cam.planeDirectionTable();
  ASSERT_EQ(table.size(), std::size_t(640 * 360));
  for (int i : {0, 1234, 640 * 200 + 17, 640 * 360 - 1}) {
    const vec3 d = cam.unprojectToPlane(vec2(float(i % 640), float(i / 640)));
    EXPECT_NEAR(table[std::size_t(i)].x, d.x, 1e-5f);
    EXPECT_NEAR(table[std::size_t(i)].y, d.y, 1e-5f);
  }
}

}  // namespace
}  // namespace holo
