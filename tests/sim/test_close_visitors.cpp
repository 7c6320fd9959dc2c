// Visitors standing close to the pyramid (SceneDescription::close_visitors) and the camera tilt:
// additive settings, so the built-in scenes' walkers must not change.
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>

#include "holo/core/error.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/visitors.hpp"
#include "shared_data.hpp"

namespace holo::sim {
namespace {

float radius(const vec3& p) {
  return std::hypot(p.x, p.z);
}

TEST(CloseVisitors, WalkersStayAsTheyAreAndTheCloseOnesStandNearTheBase) {
  SceneDescription plain = loadScene("gallery");
  SceneDescription close = plain;
  close.close_visitors = 2;
  const Museum a(plain), b(close);
  for (int frame : {0, 45, 170}) {
    const auto heads_a = a.visitorHeads(frame);
    const auto heads_b = b.visitorHeads(frame);
    ASSERT_EQ(heads_b.size(), heads_a.size() + 2);
    for (std::size_t i = 0; i < heads_a.size(); ++i) EXPECT_EQ(heads_a[i], heads_b[i]) << frame;
    for (std::size_t i = heads_a.size(); i < heads_b.size(); ++i) {
      // Feet 0.75-0.9 m from the axis, leaning 5 cm: 0.45-0.65 m from the base's side.
      EXPECT_GE(radius(heads_b[i]), 0.69f);
      EXPECT_LE(radius(heads_b[i]), 0.96f);
    }
  }
  // Their own faces: two close visitors stand a quarter turn or more apart.
  const auto heads = b.visitorHeads(0);
  const vec3 p = heads[heads.size() - 2], q = heads[heads.size() - 1];
  EXPECT_LT(glm::dot(glm::normalize(vec3(p.x, 0, p.z)), glm::normalize(vec3(q.x, 0, q.z))), 0.5f);
}

TEST(CloseVisitors, FaceThePyramidAndReachTowardsIt) {
  const auto plans = planCloseVisitors(4, 3, "atrium");
  ASSERT_EQ(plans.size(), 4u);
  for (const VisitorPlan& plan : plans) {
    EXPECT_TRUE(plan.faces_pyramid);
    const VisitorPose pose = poseAt(plan, 2.0f);
    const vec3 inward = -glm::normalize(vec3(pose.feet.x, 0.0f, pose.feet.z));
    EXPECT_NEAR(glm::dot(pose.forward, inward), 1.0f, 1e-4f);
    EXPECT_GT(plan.reach, 0.3f);
  }
  // The room has furniture by two faces: at most two close visitors there.
  EXPECT_EQ(planCloseVisitors(4, 3, "room").size(), 2u);
  EXPECT_TRUE(planCloseVisitors(0, 3, "gallery").empty());
  // The reaching hand comes no nearer the axis than the base's edge (nothing enters the pyramid).
  const Model people = buildVisitors(plans, 1.0f);
  for (const auto& mesh : people.meshes)
    for (const vec3& v : mesh.positions)
      if (v.y > -kBaseHeight + 0.05f) {
        EXPECT_GT(radius(v), kBaseHalfWidth) << mesh.name;
      }
}

TEST(CloseVisitors, TheFacingCameraSeesThemNearAndTheTiltTurnsTheRig) {
  SceneDescription d = loadScene("gallery");
  d.close_visitors = 1;
  d.camera.width = 160;
  d.camera.height = 90;
  d.noise.enabled = false;
  d.camera.tilt_deg = 20.0f;
  d.camera.vfov_deg = 90.0f;
  const Museum museum(d);
  const vec3 head = museum.visitorHeads(0).back();
  // The camera on the close visitor's side: the one whose outward axis points most at it.
  int side = 0;
  float best = -2.0f;
  for (int c = 0; c < museum.cameraCount(); ++c) {
    const vec3 axis = museum.camera(c).T_world_camera()[2];
    const float dot =
        glm::dot(glm::normalize(vec3(axis.x, 0, axis.z)), glm::normalize(vec3(head.x, 0, head.z)));
    if (dot > best) best = dot, side = c;
  }
  const SimulatedFrame f = museum.renderCamera(side, 0);
  int near = 0;
  for (int y = 0; y < f.true_depth.rows; ++y)
    for (int x = 0; x < f.true_depth.cols; ++x)
      near += f.foreground.at<std::uint8_t>(y, x) && f.true_depth.at<float>(y, x) < 0.8f;
  EXPECT_GT(near, f.true_depth.total() / 10) << "the close visitor fills a tenth of the view within 0.8 m";
  // Tilt: the optical axis rises by the tilt.
  const vec3 axis = museum.camera(side).T_world_camera()[2];
  EXPECT_NEAR(std::asin(glm::normalize(axis).y) * 180.0f / kPi, 20.0f, 0.01f);
  SceneDescription plain = loadScene("gallery");
  const vec3 axis8 = Museum(plain).camera(0).T_world_camera()[2];
  EXPECT_NEAR(std::asin(glm::normalize(axis8).y) * 180.0f / kPi, 8.0f, 0.01f);
}

TEST(CloseVisitors, SceneFileFieldsAndBadValues) {
  const auto dir = test::scratchDir("sim_close_visitors");
  const auto ok = dir / "close.yaml";
  std::ofstream(ok) << "base: gallery\nclose_visitors: 1\ncamera: {tilt_deg: 20, vfov_deg: 90}\n";
  const SceneDescription d = loadScene(ok.string());
  EXPECT_EQ(d.close_visitors, 1);
  EXPECT_FLOAT_EQ(d.camera.tilt_deg, 20.0f);
  const auto bad = dir / "bad.yaml";
  std::ofstream(bad) << "base: gallery\nclose_visitors: 7\n";
  try {
    loadScene(bad.string());
    FAIL() << "close_visitors 7 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("close_visitors"), std::string::npos) << e.what();
  }
  const auto tilt = dir / "tilt.yaml";
  std::ofstream(tilt) << "base: gallery\ncamera: {tilt_deg: 80}\n";
  EXPECT_THROW(loadScene(tilt.string()), InputError);
  SceneDescription direct = loadScene("gallery");
  direct.close_visitors = -1;
  EXPECT_THROW(Museum{direct}, InputError);
}

}  // namespace
}  // namespace holo::sim
