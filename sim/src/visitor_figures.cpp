#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/shapes.hpp"
#include "holo/sim/museum.hpp"
#include "visitor_models.hpp"

namespace holo::sim::detail {

namespace {

constexpr float kHeadRadius = 0.105f;
constexpr float kStrideLength = 0.7f;  // metres per step
constexpr float kArmShare = 0.36f;     // arm length / height

float angleAt(const VisitorPlan& p, float t) {
  if (p.faces_pyramid) return p.start_angle + p.drift * std::sin(2.0f * kPi * p.drift_hz * t + p.pace_phase);
  // Speed factor 1 + 0.6 sin(2 pi g t + phi), integrated in closed form.
  const float w = 2.0f * kPi * p.pace_hz;
  return p.start_angle +
         p.angular_speed * (t + 0.6f / w * (std::cos(p.pace_phase) - std::cos(w * t + p.pace_phase)));
}

vec3 feetAt(const VisitorPlan& p, float t) {
  const float a = angleAt(p, t);
  const float r = p.lane_radius + p.sway * std::sin(2.0f * kPi * p.sway_hz * t + p.start_angle);
  return {r * std::sin(a), -kBaseHeight, r * std::cos(a)};
}

const vec3 kSkins[] = {{0.7f, 0.5f, 0.38f}, {0.45f, 0.3f, 0.2f}, {0.25f, 0.15f, 0.1f}, {0.75f, 0.6f, 0.5f}};

}  // namespace

float figureMeanSpeed(float u) {
  return 0.4f + 0.5f * u;
}

float figureReach(const VisitorPlan& p) {
  // The hand comes to 0.55 m from the axis, a quarter metre from the glass: nearer, it would be
  // inside the depth cameras' 0.2 m minimum range, which no camera could see.
  return std::asin(std::clamp((p.lane_radius - 0.55f) / (kArmShare * p.height), 0.0f, 1.0f));
}

vec3 figureSkin(std::uint64_t draw) {
  return kSkins[draw % 4];
}

VisitorPose figurePose(const VisitorPlan& plan, float t) {
  VisitorPose pose;
  pose.feet = feetAt(plan, t);
  pose.head = pose.feet + vec3(0.0f, plan.height - kHeadRadius, 0.0f);
  if (plan.faces_pyramid) {
    const float len = std::hypot(pose.feet.x, pose.feet.z);
    pose.forward = len > 1e-7f ? vec3(-pose.feet.x / len, 0.0f, -pose.feet.z / len) : vec3(0, 0, 1);
    pose.facing_pyramid = 1.0f;
    return pose;
  }
  const vec3 v = feetAt(plan, t + 0.01f) - feetAt(plan, t - 0.01f);
  const float len = std::hypot(v.x, v.z);
  pose.forward = len > 1e-7f ? vec3(v.x / len, 0.0f, v.z / len) : vec3(0, 0, 1);
  const float walked = plan.lane_radius * std::abs(angleAt(plan, t) - plan.start_angle);
  pose.gait_phase = kPi * walked / kStrideLength;
  pose.swing = 0.4f;
  return pose;
}

void buildFigure(const VisitorPlan& p, const VisitorPose& pose, const mat4& world, const VisitorPart& part) {
  // Legs swing by +-stride, arms against them.
  const float stride = pose.swing * std::sin(pose.gait_phase);
  // Proportions from the height: hips at half, shoulders 0.29 m below the top.
  const float h = p.height;
  const float hip_y = 0.5f * h;
  const float shoulder_y = h - 0.29f;
  const float arm_length = kArmShare * h;
  const bool carrying = p.carried != Carried::nothing;

  TriangleMesh& trousers = part("trousers", p.trousers);
  for (int side : {-1, 1}) {
    const float swing = static_cast<float>(side) * stride;
    mat4 T = glm::translate(mat4(1.0f), vec3(0.095f * static_cast<float>(side), hip_y, 0.0f));
    T = glm::rotate(T, swing, vec3(1, 0, 0));
    T = glm::translate(T, vec3(0.0f, -hip_y, 0.0f));
    appendMesh(trousers, makeCylinder(0.075f, hip_y + 0.02f, 12), world * T);
  }
  TriangleMesh& shirt = part("shirt", p.shirt);
  appendMesh(shirt, makeBox({0.18f, 0.5f * (shoulder_y - hip_y) + 0.02f, 0.11f}),
             world * glm::translate(mat4(1.0f), vec3(0.0f, 0.5f * (shoulder_y + hip_y), 0.0f)));
  TriangleMesh& skin = part("skin", p.skin);
  appendMesh(skin, makeCylinder(0.05f, 0.1f, 10),
             world * glm::translate(mat4(1.0f), vec3(0.0f, shoulder_y, 0.0f)));
  appendMesh(skin, makeSphere(kHeadRadius, 10, 16),
             world * glm::translate(mat4(1.0f), vec3(0.0f, h - kHeadRadius, 0.0f)));
  vec3 hand{0.0f};
  for (int side : {-1, 1}) {
    // Side -1 carries: its arm is raised forward (book) or hangs nearly still (bag).
    const bool holds = carrying && side == -1;
    float angle = -static_cast<float>(side) * stride;  // arms swing against the legs
    if (holds) angle = p.carried == Carried::book ? -1.0f : 0.15f * angle;
    if (!holds && p.reach > 0.0f) angle = -p.reach;
    mat4 T = glm::translate(mat4(1.0f), vec3(0.23f * static_cast<float>(side), shoulder_y - 0.04f, 0.0f));
    T = glm::rotate(T, angle, vec3(1, 0, 0));
    if (holds) hand = transformPoint(T, vec3(0.0f, -arm_length, 0.0f));
    T = glm::translate(T, vec3(0.0f, -arm_length, 0.0f));
    appendMesh(shirt, makeCylinder(0.045f, arm_length, 10), world * T);
  }
  if (carrying) {
    TriangleMesh& object = part("carried", p.carried_colour);
    if (p.carried == Carried::book)  // held open in front, pages facing the visitor
      appendMesh(object, makeBox({0.14f, 0.11f, 0.025f}),
                 world * glm::translate(mat4(1.0f), hand + vec3(0.1f, 0.05f, 0.05f)));
    else  // a bag hanging from the hand
      appendMesh(object, makeBox({0.07f, 0.16f, 0.18f}),
                 world * glm::translate(mat4(1.0f), hand - vec3(0.0f, 0.17f, 0.0f)));
  }
}

}  // namespace holo::sim::detail
