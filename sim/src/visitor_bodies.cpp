#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/shapes.hpp"
#include "holo/sim/museum.hpp"
#include "visitor_models.hpp"

namespace holo::sim::detail {

namespace {

constexpr float kStrideLength = 0.7f;  // metres per step

// The pace: a walker cruises, slows down, stands, and speeds up again, once per pace cycle. The
// pace factor is clamp(kPaceBase + kPaceDepth sin(2 pi pace_hz t + pace_phase), 0, 1): cruising
// (1) for 41% of the cycle, standing (0) for 18.6% of it (a stop of 1.5-3.7 s). Divided by its
// mean (kPaceMean, 0.596) it keeps angular_speed the mean: the cruise is 1.68x that.
constexpr float kPaceBase = 0.75f, kPaceDepth = 0.9f;

// Antiderivative of the pace factor over u = 2 pi pace_hz t + pace_phase, 0 at u = 0,
// continuous and non-decreasing.
float clampedPaceIntegral(float u) {
  const float up = std::asin((1.0f - kPaceBase) / kPaceDepth);  // where it reaches 1
  const float down = std::asin(kPaceBase / kPaceDepth);         // sin u = -down: where it reaches 0
  auto F = [](float v) { return kPaceBase * v - kPaceDepth * std::cos(v); };
  enum Kind { rising, cruising, standing };
  struct Piece {
    float lo, hi;
    Kind kind;
  };
  const Piece pieces[] = {{0.0f, up, rising},
                          {up, kPi - up, cruising},
                          {kPi - up, kPi + down, rising},
                          {kPi + down, 2.0f * kPi - down, standing},
                          {2.0f * kPi - down, 2.0f * kPi, rising}};
  auto within = [&](float v) {  // v in [0, 2 pi]
    float sum = 0.0f;
    for (const Piece& p : pieces) {
      if (v <= p.lo) break;
      const float hi = std::min(v, p.hi);
      sum += p.kind == rising ? F(hi) - F(p.lo) : p.kind == cruising ? hi - p.lo : 0.0f;
    }
    return sum;
  };
  const float k = std::floor(u / (2.0f * kPi));
  return k * within(2.0f * kPi) + within(u - 2.0f * kPi * k);
}
const float kPaceMean = clampedPaceIntegral(2.0f * kPi) / (2.0f * kPi);

float angleAt(const VisitorPlan& p, float t) {
  if (p.faces_pyramid) return p.start_angle + p.drift * std::sin(2.0f * kPi * p.drift_hz * t + p.pace_phase);
  const float w = 2.0f * kPi * p.pace_hz;
  return p.start_angle + p.angular_speed / (kPaceMean * w) *
                             (clampedPaceIntegral(w * t + p.pace_phase) - clampedPaceIntegral(p.pace_phase));
}

// The pace factor before clamping: <= 0 while the visitor stands, >= 1 while it cruises.
float paceDrive(const VisitorPlan& p, float t) {
  return kPaceBase + kPaceDepth * std::sin(2.0f * kPi * p.pace_hz * t + p.pace_phase);
}

float smoothstep(float e0, float e1, float x) {
  const float u = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return u * u * (3.0f - 2.0f * u);
}

const vec3 kSkins[] = {{0.78f, 0.6f, 0.5f}, {0.7f, 0.5f, 0.38f},  {0.58f, 0.4f, 0.28f},
                       {0.45f, 0.3f, 0.2f}, {0.32f, 0.2f, 0.13f}, {0.22f, 0.14f, 0.09f}};
const vec3 kHair[] = {{0.02f, 0.015f, 0.01f}, {0.08f, 0.05f, 0.03f}, {0.2f, 0.13f, 0.06f},
                      {0.55f, 0.42f, 0.22f},  {0.45f, 0.45f, 0.44f}, {0.3f, 0.08f, 0.03f}};
const vec3 kShoes[] = {{0.03f, 0.03f, 0.03f}, {0.2f, 0.11f, 0.05f}, {0.6f, 0.6f, 0.6f}};

// Body proportions, metres, from the height (s = height / 1.75 m) and the build (widths).
struct Proportions {
  float s, build;
  float hip, torso;          // hip joints above the floor standing straight; hips to shoulder line
  float thigh, shin, ankle;  // hip to knee, knee to ankle, ankle above the floor
  float upper_arm, forearm, hand;
  float shoulder_x, hip_x;  // joints' distance from the body's midline
  float head_above_neck;    // head centre above the shoulder line
};
Proportions proportions(const VisitorPlan& p) {
  Proportions b;
  b.s = p.height / 1.75f;
  b.build = p.build;
  b.hip = 0.5f * p.height;
  b.torso = p.height - 0.29f * b.s - b.hip;
  b.ankle = 0.06f * b.s;
  b.thigh = 0.245f * p.height;
  b.shin = b.hip - b.thigh - b.ankle;
  b.upper_arm = 0.17f * p.height;
  b.forearm = 0.145f * p.height;
  b.hand = 0.1f * b.s;
  b.shoulder_x = 0.185f * b.s * p.build;
  b.hip_x = 0.09f * b.s * p.build;
  b.head_above_neck = 0.175f * b.s;
  return b;
}

// A close visitor's mean spine lean towards the pyramid, radians.
constexpr float kCloseLean = 0.06f;

vec3 feetAt(const VisitorPlan& p, float t) {
  const float a = angleAt(p, t);
  // The sway follows the distance walked (sway_hz at the mean pace), so a standing visitor's feet
  // stay put.
  const float walked_s = p.angular_speed != 0.0f ? std::abs((a - p.start_angle) / p.angular_speed) : 0.0f;
  const float sway =
      p.faces_pyramid ? 0.0f : p.sway * std::sin(2.0f * kPi * p.sway_hz * walked_s + p.start_angle);
  const float r = p.lane_radius + sway;
  return {r * std::sin(a), -kBaseHeight, r * std::cos(a)};
}

mat4 rotX(float a) {
  return glm::rotate(mat4(1.0f), a, vec3(1, 0, 0));
}

// Every bone's frame in the body's own frame (origin on the floor between the feet, +Y up, +Z
// forward); a limb hangs along its frame's -Y from the joint at its origin. Index 0 is the
// left side (x < 0), which carries; 1 the right, which reaches out.
struct Skeleton {
  mat4 pelvis, spine, neck, head;
  mat4 upper_arm[2], forearm[2], hand[2];
  mat4 thigh[2], shin[2], foot[2];
};

Skeleton articulate(const VisitorPlan& p, const VisitorPose& pose, const Proportions& b) {
  Skeleton k;
  const float phase = pose.gait_phase;
  float drop = 0.0f;
  float thigh[2], knee[2];
  for (int i = 0; i < 2; ++i) {
    const float side = i == 0 ? -1.0f : 1.0f;
    thigh[i] = side * pose.swing * std::sin(phase);
    // The knee folds while the leg swings forward (its thigh angle falling), most at mid-swing.
    const float forward = std::max(0.0f, -side * std::cos(phase));
    knee[i] = 0.05f + 1.6f * pose.swing * forward * forward;
    drop = std::max(drop, b.thigh * std::cos(thigh[i]) + b.shin * std::cos(thigh[i] + knee[i]));
  }
  // The lower foot stands on the floor: the hips bob with the gait.
  k.pelvis = glm::translate(mat4(1.0f), vec3(0.0f, drop + b.ankle, 0.0f));
  const float twist = -0.3f * pose.swing * std::sin(phase);  // shoulders turn against the hips
  k.spine = k.pelvis * rotX(pose.lean) * glm::rotate(mat4(1.0f), twist, vec3(0, 1, 0));
  k.neck = k.spine * glm::translate(mat4(1.0f), vec3(0.0f, b.torso, 0.0f));
  k.head = k.neck * rotX(-0.6f * pose.lean) *
           glm::translate(mat4(1.0f), vec3(0.0f, b.head_above_neck, 0.012f * b.s));
  for (int i = 0; i < 2; ++i) {
    const float side = i == 0 ? -1.0f : 1.0f;
    k.thigh[i] = k.pelvis * glm::translate(mat4(1.0f), vec3(side * b.hip_x, 0.0f, 0.0f)) * rotX(thigh[i]);
    k.shin[i] = k.thigh[i] * glm::translate(mat4(1.0f), vec3(0.0f, -b.thigh, 0.0f)) * rotX(knee[i]);
    k.foot[i] = k.shin[i] * glm::translate(mat4(1.0f), vec3(0.0f, -b.shin, 0.0f)) * rotX(-thigh[i] - knee[i]);

    // Angles relative to the leaning torso (positive swings back): -lean hangs plumb.
    const bool holds = i == 0 && p.carried != Carried::nothing;
    const float swing = -side * 0.8f * pose.swing * std::sin(phase);  // against the legs
    float shoulder = swing - pose.lean, elbow = -(0.2f + 0.5f * std::max(0.0f, -swing)), spread = 0.06f;
    if (holds && p.carried == Carried::book) {  // forearm level in front, the book open on it
      shoulder = -0.35f;
      elbow = -1.2f;
      spread = 0.15f;
    } else if (holds) {  // the bag's weight keeps the arm nearly still, away from the leg
      shoulder = 0.15f * swing - pose.lean;
      elbow = -0.1f;
      spread = 0.14f;
    } else if (i == 1 && p.reach > 0.0f) {
      shoulder = -p.reach - pose.lean;
      elbow = -0.08f;
      spread = 0.05f;
    }
    k.upper_arm[i] = k.spine * glm::translate(mat4(1.0f), vec3(side * b.shoulder_x, 0.93f * b.torso, 0.0f)) *
                     glm::rotate(mat4(1.0f), side * spread, vec3(0, 0, 1)) * rotX(shoulder);
    k.forearm[i] = k.upper_arm[i] * glm::translate(mat4(1.0f), vec3(0.0f, -b.upper_arm, 0.0f)) * rotX(elbow);
    k.hand[i] = k.forearm[i] * glm::translate(mat4(1.0f), vec3(0.0f, -b.forearm, 0.0f));
  }
  return k;
}

// Rings of an ellipsoid with half extents (hx, hy, hz) centred at (0, cy, cz), pole to pole.
std::vector<EllipseRing> ellipsoid(float hx, float hy, float hz, float cy = 0.0f, float cz = 0.0f,
                                   int bands = 8) {
  std::vector<EllipseRing> rings;
  for (int i = 0; i <= bands; ++i) {
    const float a = kPi * (static_cast<float>(i) / static_cast<float>(bands) - 0.5f);
    const float c = i == 0 || i == bands ? 0.0f : std::cos(a);
    rings.push_back({cy + hy * std::sin(a), hx * c, hz * c, cz});
  }
  return rings;
}

// A limb from its joint at y = 0 down to y = -length: radius r_top at the joint, r_mid halfway,
// r_end at the far end (depth = flatten x width), each end a hemisphere of its radius.
std::vector<EllipseRing> limb(float length, float r_top, float r_mid, float r_end, float flatten = 0.9f) {
  std::vector<EllipseRing> rings;
  auto ring = [&](float y, float r) { rings.push_back({y, r, flatten * r, 0.0f}); };
  for (float a : {-90.0f, -60.0f, -30.0f})
    ring(-length + r_end * std::sin(glm::radians(a)), a == -90.0f ? 0.0f : r_end * std::cos(glm::radians(a)));
  for (float f : {1.0f, 0.75f, 0.5f, 0.25f, 0.0f}) {  // f: share of the length from the joint
    // The quadratic through r_top (f = 0), r_mid (0.5) and r_end (1).
    const float r = r_top * (1.0f - f) * (1.0f - 2.0f * f) + 4.0f * r_mid * f * (1.0f - f) +
                    r_end * f * (2.0f * f - 1.0f);
    ring(-length * f, r);
  }
  for (float a : {30.0f, 60.0f, 90.0f})
    ring(r_top * std::sin(glm::radians(a)), a == 90.0f ? 0.0f : r_top * std::cos(glm::radians(a)));
  return rings;
}

}  // namespace

float bodyMeanSpeed(float u) {
  return 0.35f + 0.35f * u;
}

float bodyReach(const VisitorPlan& p) {
  // The hand's centre comes to 0.55 m from the axis, a quarter metre from the glass, at the mean
  // lean (which brings the shoulder forward): nearer, it would be inside the depth cameras' 0.2 m
  // minimum range, which no camera could see.
  const Proportions b = proportions(p);
  const float shoulder = p.lane_radius - std::sin(kCloseLean) * 0.93f * b.torso;
  const float arm = b.upper_arm + b.forearm + 0.5f * b.hand;
  return std::asin(std::clamp((shoulder - 0.55f) / arm, 0.0f, 1.0f));
}

vec3 bodySkin(std::uint64_t draw) {
  return kSkins[draw % 6];
}

void drawBodyLooks(VisitorPlan& p, PixelRng extra) {
  p.build = 0.9f + 0.25f * extra.uniform();
  p.hair_length = extra.uniform();
  p.short_sleeves = extra.uniform() < 0.4f;
  p.hair = kHair[extra.next() % 6];
  p.shoes = kShoes[extra.next() % 3];
}

VisitorPose bodyPose(const VisitorPlan& plan, float t) {
  VisitorPose pose;
  pose.feet = feetAt(plan, t);
  const float r = std::hypot(pose.feet.x, pose.feet.z);
  const vec3 inward = r > 1e-7f ? vec3(-pose.feet.x / r, 0.0f, -pose.feet.z / r) : vec3(0, 0, 1);
  const Proportions b = proportions(plan);
  if (plan.faces_pyramid) {
    pose.forward = inward;
    pose.facing_pyramid = 1.0f;
    const float sway = std::asin(std::min(plan.sway / (b.torso + b.head_above_neck), 1.0f));
    pose.lean = kCloseLean + sway * std::sin(2.0f * kPi * plan.sway_hz * t + plan.start_angle);
  } else {
    // Along the lane (the radial sway is slow beside it), turning to the pyramid while stopped.
    const float direction = plan.angular_speed < 0.0f ? -1.0f : 1.0f;
    const float a = angleAt(plan, t);
    const vec3 along = direction * vec3(std::cos(a), 0.0f, -std::sin(a));
    const float drive = paceDrive(plan, t);
    pose.facing_pyramid = 1.0f - smoothstep(0.0f, 0.3f, drive);
    pose.forward = glm::normalize(glm::mix(along, inward, pose.facing_pyramid));
    pose.gait_phase = kPi * plan.lane_radius * std::abs(a - plan.start_angle) / kStrideLength;
    pose.swing = 0.4f * smoothstep(0.0f, 0.5f, drive);
    pose.lean = 0.1f * pose.swing + 0.1f * pose.facing_pyramid;
  }
  pose.head = transformPoint(visitorFrame(pose) * articulate(plan, pose, b).head, vec3(0.0f));
  return pose;
}

void buildBody(const VisitorPlan& p, const VisitorPose& pose, const mat4& world, const VisitorPart& part) {
  const Proportions b = proportions(p);
  const Skeleton k = articulate(p, pose, b);
  auto add = [&](TriangleMesh& mesh, const std::vector<EllipseRing>& rings, const mat4& bone,
                 int segments = 16) { appendMesh(mesh, makeEllipticSweep(rings, segments), world * bone); };
  const float s = b.s, w = b.build;

  TriangleMesh& skin = part("skin", p.skin);
  add(skin, ellipsoid(0.078f * s, 0.115f * s, 0.098f * s, 0.0f, 0.005f * s), k.head);
  add(skin, limb(0.15f * s, 0.052f * s, 0.05f * s, 0.055f * s),
      k.neck * glm::translate(mat4(1.0f), vec3(0.0f, 0.12f * s, 0.0f)));
  TriangleMesh& hair = part("hair", p.hair);
  // Over the crown and down the back of the head, lower for long hair; the face stays bare.
  add(hair,
      ellipsoid(1.08f * 0.078f * s, 0.115f * s * (0.75f + 0.3f * p.hair_length), 1.1f * 0.098f * s,
                0.115f * s * (0.3f - 0.3f * p.hair_length), -0.025f * s),
      k.head);

  TriangleMesh& shirt = part("shirt", p.shirt);
  std::vector<EllipseRing> torso;
  const float L = b.torso;
  for (const vec4& r : {vec4(0.02f * L, 0.0f, 0.0f, 0.0f), vec4(0.06f * L, 0.125f, 0.09f, 0.0f),
                        vec4(0.3f * L, 0.12f, 0.085f, 0.0f), vec4(0.55f * L, 0.14f, 0.095f, 0.008f),
                        vec4(0.78f * L, 0.155f, 0.1f, 0.01f), vec4(0.93f * L, 0.16f, 0.09f, 0.0f),
                        vec4(L, 0.14f, 0.07f, 0.0f), vec4(L + 0.035f * s, 0.08f, 0.045f, 0.0f),
                        vec4(L + 0.045f * s, 0.0f, 0.0f, 0.0f)})
    torso.push_back({r.x, r.y * s * w, r.z * s * (0.5f + 0.5f * w), r.w * s});
  add(shirt, torso, k.spine, 20);
  TriangleMesh& trousers = part("trousers", p.trousers);
  add(trousers, ellipsoid(0.165f * s * w, 0.11f * s, 0.11f * s, 0.03f * s, -0.005f * s), k.pelvis);
  TriangleMesh& shoes = part("shoes", p.shoes);
  for (int side = 0; side < 2; ++side) {
    add(shirt, limb(b.upper_arm, 0.052f * s, 0.047f * s, 0.038f * s), k.upper_arm[side]);
    add(p.short_sleeves ? skin : shirt, limb(b.forearm, 0.038f * s, 0.036f * s, 0.027f * s), k.forearm[side]);
    add(skin, ellipsoid(0.018f * s, 0.5f * b.hand, 0.042f * s, -0.5f * b.hand), k.hand[side]);
    add(trousers, limb(b.thigh, 0.085f * s * w, 0.07f * s * w, 0.052f * s), k.thigh[side]);
    add(trousers, limb(b.shin, 0.052f * s, 0.055f * s, 0.036f * s), k.shin[side]);
    add(shoes, ellipsoid(0.048f * s, 0.04f * s, 0.13f * s, -0.02f * s, 0.045f * s), k.foot[side]);
  }
  if (p.carried != Carried::nothing) {
    TriangleMesh& object = part("carried", p.carried_colour);
    if (p.carried == Carried::book)  // open on the left forearm, pages tilted to the face
      appendMesh(object, makeBox({0.14f, 0.11f, 0.02f}),
                 world * k.forearm[0] * glm::translate(mat4(1.0f), vec3(0.06f, -b.forearm - 0.02f, 0.05f)) *
                     rotX(0.3f));
    else  // hanging plumb from the left hand
      appendMesh(object, makeBox({0.07f, 0.16f, 0.18f}),
                 world * glm::translate(mat4(1.0f),
                                        transformPoint(k.hand[0], vec3(0.0f, -0.5f * b.hand - 0.14f, 0.0f))));
  }
}

}  // namespace holo::sim::detail
