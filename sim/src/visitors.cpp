#include "holo/sim/visitors.hpp"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/error.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "visitor_models.hpp"

namespace holo::sim {

namespace {

// Lanes per hall: close to the pyramid (its furniture stands within ~1.2 m) and inside the walls.
void laneLimits(const std::string& hall, float& inner, float& outer) {
  inner = 1.2f;
  outer = hall == "room" ? 1.75f : hall == "gallery" ? 2.3f : hall == "atrium" ? 3.2f : 2.6f;
}

// The palettes both models draw from (skins are each model's own).
const vec3 kShirts[] = {{0.55f, 0.08f, 0.06f}, {0.08f, 0.35f, 0.1f}, {0.1f, 0.15f, 0.55f},
                        {0.6f, 0.45f, 0.05f},  {0.45f, 0.1f, 0.4f},  {0.05f, 0.4f, 0.45f},
                        {0.6f, 0.6f, 0.58f},   {0.6f, 0.25f, 0.05f}};
const vec3 kTrousers[] = {
    {0.04f, 0.05f, 0.12f}, {0.08f, 0.08f, 0.08f}, {0.2f, 0.17f, 0.12f}, {0.02f, 0.02f, 0.02f}};
const vec3 kCarried[] = {{0.85f, 0.02f, 0.02f}, {0.9f, 0.8f, 0.0f}, {0.0f, 0.7f, 0.1f},
                         {0.8f, 0.0f, 0.6f},    {0.0f, 0.6f, 0.8f}, {0.95f, 0.35f, 0.0f}};

// Height, skin, shirt and trousers from the visitor's stream `rng`; a body's build, hair, sleeves
// and shoes from a stream of their own (`extra`), so what the path's stream draws after the looks
// (what is carried) is the same for both models.
void drawLooks(VisitorPlan& p, PixelRng& rng, PixelRng extra) {
  const bool body = p.model == VisitorModel::bodies;
  p.height = 1.55f + 0.35f * rng.uniform();
  p.skin = body ? detail::bodySkin(rng.next()) : detail::figureSkin(rng.next());
  p.shirt = kShirts[rng.next() % 8];
  p.trousers = kTrousers[rng.next() % 4];
  if (body) detail::drawBodyLooks(p, extra);
}

}  // namespace

namespace detail {
mat4 visitorFrame(const VisitorPose& pose) {
  const float yaw = std::atan2(pose.forward.x, pose.forward.z);
  return glm::rotate(glm::translate(mat4(1.0f), pose.feet), yaw, vec3(0, 1, 0));
}
}  // namespace detail

std::vector<VisitorPlan> planVisitors(int count, std::uint64_t seed, const std::string& hall,
                                      VisitorModel model) {
  float inner = 0, outer = 0;
  laneLimits(hall, inner, outer);
  const int n = std::max(count, 0);
  const float lane = n > 0 ? (outer - inner) / static_cast<float>(n) : 0.0f;
  std::vector<VisitorPlan> plans;
  for (int i = 0; i < n; ++i) {
    PixelRng rng(seed, 0x7151708ull, i, 0);
    VisitorPlan p;
    p.model = model;
    p.lane_radius = inner + lane * (static_cast<float>(i) + 0.35f + 0.3f * rng.uniform());
    p.sway = 0.15f * lane * rng.uniform();
    p.sway_hz = 0.05f + 0.1f * rng.uniform();
    p.start_angle = 2.0f * kPi * rng.uniform();
    const float u = rng.uniform();
    const float speed = model == VisitorModel::bodies ? detail::bodyMeanSpeed(u) : detail::figureMeanSpeed(u);
    p.angular_speed = (rng.uniform() < 0.5f ? -1.0f : 1.0f) * speed / p.lane_radius;
    p.pace_hz = 0.05f + 0.07f * rng.uniform();
    p.pace_phase = 2.0f * kPi * rng.uniform();
    drawLooks(p, rng, PixelRng(seed, 0x7151709ull, i, 0));
    // The first visitor always carries something, so every scene with visitors shows the case.
    if (i == 0 || rng.uniform() < 0.6f) {
      p.carried = (i + static_cast<int>(rng.next() % 2)) % 2 == 0 ? Carried::book : Carried::bag;
      p.carried_colour = kCarried[rng.next() % 6];
    }
    plans.push_back(p);
  }
  return plans;
}

std::vector<VisitorPlan> planCloseVisitors(int count, std::uint64_t seed, const std::string& hall,
                                           VisitorModel model) {
  // Faces (0..3: +Z, +X, -Z, -X) with room to stand: the room has its side table on +X and its
  // plant towards -Z; the gallery's info pole and the atrium's bollards stand on the diagonals;
  // in the window hall the one close visitor stands between the window (+Z) and the relic.
  const std::vector<int> faces = hall == "room"     ? std::vector<int>{0, 3}
                                 : hall == "window" ? std::vector<int>{0}
                                                    : std::vector<int>{0, 1, 2, 3};
  const int n = std::clamp(count, 0, static_cast<int>(faces.size()));
  std::vector<VisitorPlan> plans;
  const std::size_t first_face =
      static_cast<std::size_t>(PixelRng(seed, 0xC105E0ull, 0, 0).next() % faces.size());
  for (int i = 0; i < n; ++i) {
    PixelRng rng(seed, 0xC105E1ull, i, 0);
    VisitorPlan p;
    p.model = model;
    p.faces_pyramid = true;
    p.lane_radius = 0.75f + 0.15f * rng.uniform();
    p.sway = 0.05f;  // leaning in and out
    p.sway_hz = 0.1f + 0.1f * rng.uniform();
    const int face = faces[(first_face + static_cast<std::size_t>(i)) % faces.size()];
    p.start_angle = 0.5f * kPi * static_cast<float>(face) + 0.2f * (rng.uniform() - 0.5f);
    p.angular_speed = 0.0f;
    p.drift = 0.1f + 0.1f * rng.uniform();
    p.drift_hz = 0.03f + 0.04f * rng.uniform();
    // The shuffle's phase: the bodies were measured with every close visitor starting in phase
    // (docs/sim.md), so their stream draws none.
    if (model == VisitorModel::figures) p.pace_phase = 2.0f * kPi * rng.uniform();
    drawLooks(p, rng, PixelRng(seed, 0xC105E2ull, i, 0));
    p.reach = model == VisitorModel::bodies ? detail::bodyReach(p) : detail::figureReach(p);
    if (i == 0) {  // a bag: a book held up in front would reach into the pyramid
      p.carried = Carried::bag;
      p.carried_colour = kCarried[rng.next() % 6];
    }
    plans.push_back(p);
  }
  return plans;
}

VisitorPose poseAt(const VisitorPlan& plan, float t) {
  return plan.model == VisitorModel::bodies ? detail::bodyPose(plan, t) : detail::figurePose(plan, t);
}

Model buildVisitors(const std::vector<VisitorPlan>& plans, float t) {
  Model model;
  // part() hands out references into meshes: reserve so no push_back moves them (a body has the
  // most materials, 6).
  model.meshes.reserve(6 * plans.size());
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const VisitorPlan& p = plans[i];
    const VisitorPose pose = poseAt(p, t);
    const detail::VisitorPart part = [&](const std::string& what, const vec3& radiance) -> TriangleMesh& {
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
    if (p.model == VisitorModel::bodies)
      detail::buildBody(p, pose, detail::visitorFrame(pose), part);
    else
      detail::buildFigure(p, pose, detail::visitorFrame(pose), part);
  }
  return model;
}

}  // namespace holo::sim
