#include "holo/eval/caustic_evaluation.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/shapes.hpp"
#include "holo/core/stats.hpp"
#include "holo/reflect/caustic_tracer.hpp"

namespace holo::eval {

namespace {
float radians(float degrees) {
  return degrees * kPi / 180.0f;
}
vec3 sphereCentre(const CausticScene& s) {
  return {0.0f, s.centre_height, 0.0f};
}
vec3 towardsLight(const CausticScene& s) {
  const float a = radians(s.light_angle_deg);
  return {std::sin(a), std::cos(a), 0.0f};
}
}  // namespace

Model causticSphere(const CausticScene& scene, bool opaque) {
  Model model;
  TriangleMesh mesh = makeSphere(scene.radius, 128, 256);
  for (vec3& p : mesh.positions) p += sphereCentre(scene);
  mesh.material = 0;
  model.meshes.push_back(std::move(mesh));
  Material m;
  m.name = opaque ? "metal" : "glass";
  m.base_colour = vec3(1.0f);
  m.roughness = 0.0f;
  if (opaque) {
    m.metallic = 1.0f;
  } else {
    m.transmission = 1.0f;
    m.thickness = 2.0f * scene.radius;
    m.ior = scene.ior;
  }
  model.materials.push_back(m);
  return model;
}

reference::PointLight causticLight(const CausticScene& scene) {
  return {sphereCentre(scene) + scene.light_distance * towardsLight(scene), vec3(scene.light_power)};
}

vec2 causticAxisPoint(const CausticScene& scene) {
  const vec3 d = -towardsLight(scene);
  const vec3 p = sphereCentre(scene) + (scene.centre_height / -d.y) * d;
  return {p.x, p.z};
}

reference::CausticReceiver causticReceiver(const CausticScene& scene) {
  return {0.0f, causticAxisPoint(scene), 2.0f * scene.radius};
}

cv::Mat receiverIrradiance(const CausticScene& s, bool opaque, const reference::ReceiverImage& caustic) {
  const Model sphere = causticSphere(s, opaque);
  const reflect::RenderScene scene(sphere, {});
  const reference::PointLight light = causticLight(s);
  cv::Mat out = caustic.irradiance.clone();
  for (int row = 0; row < out.rows; ++row)
    for (int column = 0; column < out.cols; ++column) {
      const vec2 c = caustic.cellCentre(column, row);
      const vec3 p(c.x, caustic.receiver.height, c.y);
      const vec3 to_light = light.position - p;
      const float d2 = glm::dot(to_light, to_light);
      const vec3 w = to_light / std::sqrt(d2);
      if (scene.relicOnly().intersect(Ray{p, w}).hit()) continue;
      const vec3 e = light.power * (w.y / (4.0f * kPi * d2));
      out.at<cv::Vec3f>(row, column) += cv::Vec3f(e.z, e.y, e.x);
    }
  return out;
}

CausticEvaluation evaluateCaustics(const CausticEvaluationOptions& o) {
  const Model sphere = causticSphere(o.scene, o.opaque);
  const reflect::RenderScene scene(sphere, {});
  const reference::PointLight light = causticLight(o.scene);
  const reference::CausticReceiver receiver = causticReceiver(o.scene);
  CausticEvaluation e;
  e.plan = reference::planCaustics(scene, receiver, light);
  e.axis_point = causticAxisPoint(o.scene);
  const std::int64_t traced_before = stats::counter("Caustics/Photons traced").load();
  const std::int64_t stored_before = stats::counter("Caustics/Photons stored").load();

  reference::PhotonTracingOptions tracing;
  tracing.seed = o.seed;
  const auto photons = reference::tracePhotons(scene, receiver, light, 0, o.photons, o.photons, tracing);
  e.photon_map = reference::photonMapEstimate(photons, receiver, o.resolution,
                                              o.kernel_radius_over_radius * o.scene.radius);
  tracing.seed = o.seed + 1;
  reference::LightTracerImage light_tracer(receiver, o.resolution);
  constexpr std::uint64_t kBatch = 1u << 20;
  for (std::uint64_t first = 0; first < o.reference_photons; first += kBatch)
    light_tracer.addPhotons(reference::tracePhotons(scene, receiver, light, first,
                                                    std::min(kBatch, o.reference_photons - first),
                                                    o.reference_photons, tracing));
  e.light_tracer = light_tracer.image();
  e.photons_traced = stats::counter("Caustics/Photons traced").load() - traced_before;
  e.photons_stored = stats::counter("Caustics/Photons stored").load() - stored_before;

  const float window = 0.1f * o.scene.radius;
  e.peak = reference::causticPeak(e.photon_map, window);
  e.reference_peak = reference::causticPeak(e.light_tracer, window);
  e.power = reference::causticPower(e.photon_map, e.reference_peak, o.scene.radius);
  e.reference_power = reference::causticPower(e.light_tracer, e.reference_peak, o.scene.radius);
  const double spot = double(window) * double(window) * double(kPi);
  e.peak_irradiance = reference::causticPower(e.photon_map, e.reference_peak, window) / spot;
  e.reference_peak_irradiance = reference::causticPower(e.light_tracer, e.reference_peak, window) / spot;

  // The live light tracer (reflect/caustic_tracer.hpp) on the same receiver grid, as the appliance
  // runs it (its smoothing included).
  if (o.live_photons > 0) {
    reflect::CausticReceiverGrid grid;
    grid.centre = receiver.centre;
    grid.half_size = receiver.half_size;
    grid.height = receiver.height;
    grid.resolution = o.resolution;
    reflect::CausticTracerSettings live;
    live.photons = o.live_photons;
    live.seed = o.seed + 2;
    const reflect::CausticImage image =
        reflect::tracePointCaustics(scene, light.position, light.power, grid, live);
    e.live.receiver = receiver;
    e.live.resolution = o.resolution;
    e.live.irradiance = image.irradiance;
    e.live_ms = image.ms;
    e.live_photons_stored = image.stored;
    e.live_peak = reference::causticPeak(e.live, window);
    e.live_power = reference::causticPower(e.live, e.reference_peak, o.scene.radius);
    e.live_peak_irradiance = reference::causticPower(e.live, e.reference_peak, window) / spot;
  }
  return e;
}

}  // namespace holo::eval
