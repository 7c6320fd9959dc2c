#include "holo/sim/visitors.hpp"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "holo/sim/shapes.hpp"

namespace holo::sim {

namespace {

constexpr float kHeadRadius = 0.105f;
constexpr float kStrideLength = 0.7f;  // metres per step

// Lanes per hall: close to the pyramid (its furniture stands within ~1.2 m) and inside the walls.
void laneLimits(const std::string& hall, float& inner, float& outer) {
  inner = 1.2f;
  outer = hall == "room" ? 1.75f : hall == "gallery" ? 2.3f : hall == "atrium" ? 3.2f : 2.6f;
}

float angleAt(const VisitorPlan& p, float t) {
  if (p.faces_pyramid) return p.start_angle + p.drift * std::sin(2.0f * kPi * p.drift_hz * t + p.pace_phase);
  // Speed factor 1 + 0.6 sin(2 pi g t + phi), integrated in closed form.
  const float w = 2.0f * kPi * p.pace_hz;
  return p.start_angle +
         p.angular_speed * (t + 0.6f / w * (std::cos(p.pace_phase) - std::cos(w * t + p.pace_phase)));
}

// The palettes every visitor draws from.
const vec3 kShirts[] = {{0.55f, 0.08f, 0.06f}, {0.08f, 0.35f, 0.1f}, {0.1f, 0.15f, 0.55f},
                        {0.6f, 0.45f, 0.05f},  {0.45f, 0.1f, 0.4f},  {0.05f, 0.4f, 0.45f},
                        {0.6f, 0.6f, 0.58f},   {0.6f, 0.25f, 0.05f}};
const vec3 kTrousers[] = {
    {0.04f, 0.05f, 0.12f}, {0.08f, 0.08f, 0.08f}, {0.2f, 0.17f, 0.12f}, {0.02f, 0.02f, 0.02f}};
const vec3 kSkins[] = {{0.7f, 0.5f, 0.38f}, {0.45f, 0.3f, 0.2f}, {0.25f, 0.15f, 0.1f}, {0.75f, 0.6f, 0.5f}};
const vec3 kCarried[] = {{0.85f, 0.02f, 0.02f}, {0.9f, 0.8f, 0.0f}, {0.0f, 0.7f, 0.1f},
                         {0.8f, 0.0f, 0.6f},    {0.0f, 0.6f, 0.8f}, {0.95f, 0.35f, 0.0f}};

vec3 feetAt(const VisitorPlan& p, float t) {
  const float a = angleAt(p, t);
  const float r = p.lane_radius + p.sway * std::sin(2.0f * kPi * p.sway_hz * t + p.start_angle);
  return {r * std::sin(a), -kBaseHeight, r * std::cos(a)};
}

}  // namespace

std::vector<VisitorPlan> planVisitors(int count, std::uint64_t seed, const std::string& hall) {
  float inner = 0, outer = 0;
  laneLimits(hall, inner, outer);
  const int n = std::max(count, 0);
  const float lane = n > 0 ? (outer - inner) / static_cast<float>(n) : 0.0f;
  std::vector<VisitorPlan> plans;
  for (int i = 0; i < n; ++i) {
    PixelRng rng(seed, 0x7151708ull, i, 0);
    VisitorPlan p;
    p.lane_radius = inner + lane * (static_cast<float>(i) + 0.35f + 0.3f * rng.uniform());
    p.sway = 0.15f * lane * rng.uniform();
    p.sway_hz = 0.05f + 0.1f * rng.uniform();
    p.start_angle = 2.0f * kPi * rng.uniform();
    const float speed = 0.4f + 0.5f * rng.uniform();
    p.angular_speed = (rng.uniform() < 0.5f ? -1.0f : 1.0f) * speed / p.lane_radius;
    p.pace_hz = 0.05f + 0.07f * rng.uniform();
    p.pace_phase = 2.0f * kPi * rng.uniform();
    p.height = 1.55f + 0.35f * rng.uniform();
    p.skin = kSkins[rng.next() % 4];
    p.shirt = kShirts[rng.next() % 8];
    p.trousers = kTrousers[rng.next() % 4];
    // The first visitor always carries something, so every scene with visitors shows the case.
    if (i == 0 || rng.uniform() < 0.6f) {
      p.carried = (i + static_cast<int>(rng.next() % 2)) % 2 == 0 ? Carried::book : Carried::bag;
      p.carried_colour = kCarried[rng.next() % 6];
    }
    plans.push_back(p);
  }
  return plans;
}

std::vector<VisitorPlan> planCloseVisitors(int count, std::uint64_t seed, const std::string& hall) {
  // Faces (0..3: +Z, +X, -Z, -X) with room to stand: the room has its side table on +X and its
  // plant towards -Z; the gallery's info pole and the atrium's bollards stand on the diagonals.
  const std::vector<int> faces = hall == "room" ? std::vector<int>{0, 3} : std::vector<int>{0, 1, 2, 3};
  const int n = std::clamp(count, 0, static_cast<int>(faces.size()));
  std::vector<VisitorPlan> plans;
  const std::size_t first_face =
      static_cast<std::size_t>(PixelRng(seed, 0xC105E0ull, 0, 0).next() % faces.size());
  for (int i = 0; i < n; ++i) {
    PixelRng rng(seed, 0xC105E1ull, i, 0);
    VisitorPlan p;
    p.faces_pyramid = true;
    p.lane_radius = 0.75f + 0.15f * rng.uniform();
    p.sway = 0.05f;  // leaning in and out
    p.sway_hz = 0.1f + 0.1f * rng.uniform();
    const int face = faces[(first_face + static_cast<std::size_t>(i)) % faces.size()];
    p.start_angle = 0.5f * kPi * static_cast<float>(face) + 0.2f * (rng.uniform() - 0.5f);
    p.angular_speed = 0.0f;
    p.drift = 0.1f + 0.1f * rng.uniform();
    p.drift_hz = 0.03f + 0.04f * rng.uniform();
    p.pace_phase = 2.0f * kPi * rng.uniform();
    p.height = 1.55f + 0.35f * rng.uniform();
    p.skin = kSkins[rng.next() % 4];
    p.shirt = kShirts[rng.next() % 8];
    p.trousers = kTrousers[rng.next() % 4];
    // The hand comes to 0.55 m from the axis, a quarter metre from the glass, at the mean lean
    // (the arm is 0.36 height long, buildVisitors): nearer, it would be inside the depth cameras'
    // 0.2 m minimum range, which no camera could see.
    const float arm = 0.36f * p.height;
    p.reach = std::asin(std::clamp((p.lane_radius - 0.55f) / arm, 0.0f, 1.0f));
    if (i == 0) {  // a bag: a book held up in front would reach into the pyramid
      p.carried = Carried::bag;
      p.carried_colour = kCarried[rng.next() % 6];
    }
    plans.push_back(p);
  }
  return plans;
}

VisitorPose poseAt(const VisitorPlan& plan, float t) {
  VisitorPose pose;
  pose.feet = feetAt(plan, t);
  if (plan.faces_pyramid) {
    const float len = std::hypot(pose.feet.x, pose.feet.z);
    pose.forward = len > 1e-7f ? vec3(-pose.feet.x / len, 0.0f, -pose.feet.z / len) : vec3(0, 0, 1);
    pose.stride = 0.0f;
    pose.head = pose.feet + vec3(0.0f, plan.height - kHeadRadius, 0.0f);
    return pose;
  }
  const vec3 v = feetAt(plan, t + 0.01f) - feetAt(plan, t - 0.01f);
  const float len = std::hypot(v.x, v.z);
  pose.forward = len > 1e-7f ? vec3(v.x / len, 0.0f, v.z / len) : vec3(0, 0, 1);
  const float walked = plan.lane_radius * std::abs(angleAt(plan, t) - plan.start_angle);
  pose.stride = 0.4f * std::sin(kPi * walked / kStrideLength);
  pose.head = pose.feet + vec3(0.0f, plan.height - kHeadRadius, 0.0f);
  return pose;
}

Model buildVisitors(const std::vector<VisitorPlan>& plans, float t) {
  Model model;
  // part() hands out references into meshes: reserve so no push_back moves them.
  model.meshes.reserve(4 * plans.size());
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const VisitorPlan& p = plans[i];
    const VisitorPose pose = poseAt(p, t);
    const float yaw = std::atan2(pose.forward.x, pose.forward.z);
    const mat4 world = glm::rotate(glm::translate(mat4(1.0f), pose.feet), yaw, vec3(0, 1, 0));
    auto part = [&](const std::string& what, const vec3& radiance) -> TriangleMesh& {
      Material m;
      m.name = "visitor" + std::to_string(i) + "_" + what;
      m.base_colour = glm::clamp(radiance, 0.0f, 1.0f);
      m.emission = radiance;
      model.materials.push_back(m);
      TriangleMesh mesh;
      mesh.name = m.name;
      mesh.material = static_cast<int>(model.materials.size() - 1);
      model.meshes.push_back(std::move(mesh));
      return model.meshes.back();
    };
    // Proportions from the height: hips at half, shoulders 0.29 m below the top.
    const float h = p.height;
    const float hip_y = 0.5f * h;
    const float shoulder_y = h - 0.29f;
    const float arm_length = 0.36f * h;
    const bool carrying = p.carried != Carried::nothing;

    TriangleMesh& trousers = part("trousers", p.trousers);
    for (int side : {-1, 1}) {
      const float swing = static_cast<float>(side) * pose.stride;
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
      float angle = -static_cast<float>(side) * pose.stride;  // arms swing against the legs
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
  return model;
}

}  // namespace holo::sim
