// The AR composite on one REAL Kinect frame (../shared/data rgbd/tum: an office, 640x480, depth
// registered to colour) under a real interior panorama (hdri/st_fagans_interior_1k.hdr): a sphere
// placed on the floor between the chairs, the world frame fitted to the floor there (origin at
// the floor under pixel (300, 420), +Y its normal). The composite shows the sphere, darkens the
// floor around where it stands, and leaves everything beyond the local scene as the camera saw it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ar_test_scene.hpp"
#include "holo/ar/ar_view.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "shared_data.hpp"

namespace holo::ar {
namespace {

constexpr float kTumMetresPerUnit = 1.0f / 5000.0f;

float luminance(const cv::Vec3b& bgr) {
  return 0.2126f * srgbToLinear(bgr[2] / 255.0f) + 0.7152f * srgbToLinear(bgr[1] / 255.0f) +
         0.0722f * srgbToLinear(bgr[0] / 255.0f);
}

TEST(ArRealFrame, ASphereOnTheFloorOfARealOfficeCastsItsShadowThere) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum/color.png");
  HOLO_REQUIRE_SHARED_DATA("hdri/st_fagans_interior_1k.hdr");
  RgbdFrame frame;
  frame.colour = cv::imread(holo::test::sharedData("rgbd/tum/color.png").string(), cv::IMREAD_COLOR);
  const cv::Mat raw = cv::imread(holo::test::sharedData("rgbd/tum/depth.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  raw.convertTo(frame.depth, CV_32FC1, kTumMetresPerUnit);
  Intrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = K.fy = 525.0f;
  K.cx = 319.5f;
  K.cy = 239.5f;
  const CameraModel unposed(K, mat4(1.0f));  // camera frame = world frame, to fit the floor
  const auto at = [&](int x, int y) {
    return unposed.unproject({static_cast<float>(x), static_cast<float>(y)}, frame.depth.at<float>(y, x));
  };
  const vec3 floor = at(300, 420);
  ASSERT_GT(floor.z, 0.5f);
  vec3 up = glm::normalize(glm::cross(at(300, 435) - at(300, 405), at(315, 420) - at(285, 420)));
  if (up.y > 0.0f) up = -up;  // camera +Y is down: the floor's normal points to -Y
  const vec3 x_axis = glm::normalize(glm::cross(up, vec3(0.0f, 0.0f, 1.0f)));
  const vec3 z_axis = glm::cross(x_axis, up);
  mat4 T_camera_world(1.0f);
  T_camera_world[0] = vec4(x_axis, 0.0f);
  T_camera_world[1] = vec4(up, 0.0f);
  T_camera_world[2] = vec4(z_axis, 0.0f);
  T_camera_world[3] = vec4(floor, 1.0f);
  const CameraModel camera(K, glm::inverse(T_camera_world));
  requireArCameraInputs(0, camera, frame);

  // The panorama scaled so the floor's albedo comes out about 0.5 (what an installation's
  // exposure calibration does).
  cv::Mat panorama = loadHdr(holo::test::sharedData("hdri/st_fagans_interior_1k.hdr")).pixels;
  const vec3 E = reflect::IrradianceSH(reflect::Environment(panorama)).irradiance({0.0f, 1.0f, 0.0f});
  const float floor_radiance = luminance(frame.colour.at<cv::Vec3b>(420, 300));
  panorama *= glm::pi<float>() * floor_radiance / 0.5f / (0.2126f * E.r + 0.7152f * E.g + 0.0722f * E.b);

  ArViewSettings settings;
  settings.composite.spp = 8;
  settings.surface.radius = 1.0f;
  const ArView view = renderArView(0, camera, frame, test::sphereRelic(), panorama, settings);
  EXPECT_GT(view.relic_pixels, 300);
  EXPECT_GT(view.real_vertices, 10000u);

  // Around the contact point: the floor within 1.2-2 sphere radii of it, seen beside the sphere,
  // in eight sectors of azimuth; the shadow falls away from the panorama's brightest light.
  std::array<double, 8> before{}, after{};
  int ring = 0, beyond_changed = 0, beyond = 0;
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const float z = frame.depth.at<float>(y, x);
      if (!(z > 0.0f)) continue;
      const vec3 p = camera.unproject({static_cast<float>(x), static_cast<float>(y)}, z);
      const float r = glm::length(vec2(p.x, p.z));
      if (glm::length(p) > 1.2f) {
        ++beyond;
        beyond_changed += view.image.at<cv::Vec3b>(y, x) != frame.colour.at<cv::Vec3b>(y, x) ? 1 : 0;
      }
      if (std::abs(p.y) > 0.02f || r < 0.14f || r > 0.24f) continue;
      if (view.image.at<cv::Vec3b>(y, x) == cv::Vec3b(0, 0, 0)) continue;
      const float azimuth = std::atan2(p.z, p.x) + glm::pi<float>();
      const auto sector =
          std::min<std::size_t>(7, static_cast<std::size_t>(azimuth / (glm::pi<float>() / 4.0f)));
      before[sector] += luminance(frame.colour.at<cv::Vec3b>(y, x));
      after[sector] += luminance(view.image.at<cv::Vec3b>(y, x));
      ++ring;
    }
  ASSERT_GT(ring, 100);
  double darkest = 1.0;
  for (std::size_t i = 0; i < before.size(); ++i)
    if (before[i] > 0) darkest = std::min(darkest, after[i] / before[i]);
  EXPECT_LT(darkest, 0.93) << "the floor darkens on one side of the sphere";  // 0.88 measured
  EXPECT_GT(beyond, 10000);
  EXPECT_EQ(beyond_changed, 0) << "beyond the local scene the camera's image is kept";
}

}  // namespace
}  // namespace holo::ar
