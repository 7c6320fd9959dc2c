#include "holo/eval/ar_evaluation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <ctime>

#include "holo/ar/ar_view.hpp"
#include "holo/ar/change_filter.hpp"
#include "holo/ar/change_region.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/ar/relic_caustic.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/sensor_noise.hpp"

namespace holo::eval {
namespace {

// CPU time of the process's threads (all cores together) since `start`: the machine's other
// load does not count, and a method's cost is the same whatever the cores.
double cpuMsSince(std::clock_t start) {
  return 1000.0 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

float luminance(const vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// The part of a triangle within the sphere, as small triangles: kept whole inside, dropped
// outside, split in four across the boundary down to edges of `finest` metres (then kept when
// its centroid is inside).
void clipToSphere(const vec3& a, const vec3& b, const vec3& c, const vec3& centre, float radius, float finest,
                  const vec3& albedo, ar::RealSurface& out) {
  const auto inside = [&](const vec3& p) { return glm::length(p - centre) <= radius; };
  const auto keep = [&] {
    const auto first = static_cast<unsigned>(out.mesh.positions.size());
    for (const vec3& p : {a, b, c}) {
      out.mesh.positions.push_back(p);
      out.albedo.push_back(albedo);
    }
    out.mesh.triangles.push_back({first, first + 1, first + 2});
  };
  if (inside(a) && inside(b) && inside(c)) return keep();
  // Farther than the radius from every point of the triangle: its closest point is outside.
  const vec3 centroid = (a + b + c) / 3.0f;
  const float extent =
      std::max({glm::length(a - centroid), glm::length(b - centroid), glm::length(c - centroid)});
  if (glm::length(centroid - centre) > radius + extent) return;
  const float longest = std::max({glm::length(a - b), glm::length(b - c), glm::length(c - a)});
  if (longest <= finest) {
    if (inside(centroid)) keep();
    return;
  }
  const vec3 ab = 0.5f * (a + b), bc = 0.5f * (b + c), ca = 0.5f * (c + a);
  clipToSphere(a, ab, ca, centre, radius, finest, albedo, out);
  clipToSphere(ab, b, bc, centre, radius, finest, albedo, out);
  clipToSphere(ca, bc, c, centre, radius, finest, albedo, out);
  clipToSphere(ab, bc, ca, centre, radius, finest, albedo, out);
}

// The hall's surfaces within the local radius, Lambertian with their base colour (flat normals).
ar::RealSurface trueLocalSurface(const Model& hall, float radius) {
  ar::RealSurface out;
  for (const TriangleMesh& mesh : hall.meshes) {
    const auto index = static_cast<std::size_t>(mesh.material);
    const vec3 albedo = glm::clamp(
        index < hall.materials.size() ? hall.materials[index].base_colour : vec3(0.5f), 0.0f, kTrueAlbedoMax);
    for (const uvec3& t : mesh.triangles)
      clipToSphere(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z], vec3(0.0f), radius, 0.05f,
                   albedo, out);
  }
  out.mesh.name = "hall within the local radius";
  out.mesh.computeNormals();
  return out;
}

// The hall's depth and incidence cosine through the camera (0 where out of range).
void hallDepth(const Model& hall, const CameraModel& camera, const sim::CameraSettings& settings,
               cv::Mat& depth, cv::Mat& cosine) {
  RayScene scene;
  for (const TriangleMesh& mesh : hall.meshes) scene.addMesh(mesh);
  scene.commit();
  depth = cv::Mat::zeros(camera.height(), camera.width(), CV_32FC1);
  cosine = cv::Mat::zeros(camera.height(), camera.width(), CV_32FC1);
  const vec3 forward = glm::normalize(vec3(camera.T_world_camera()[2]));
  tbb::parallel_for(0, camera.height(), [&](int y) {
    for (int x = 0; x < camera.width(); ++x) {
      const Ray ray = camera.ray({static_cast<float>(x), static_cast<float>(y)});
      const RayHit hit = scene.intersect(ray);
      if (!hit.hit()) continue;
      const float z = hit.t * glm::dot(ray.direction, forward);
      if (z >= settings.min_range && z <= settings.max_range) depth.at<float>(y, x) = z;
      cosine.at<float>(y, x) = std::abs(glm::dot(ray.direction, hit.geometric_normal));
    }
  });
}

cv::Mat accumulate(const cv::Mat& sum, const cv::Mat& pass) {
  return sum.empty() ? pass.clone() : cv::Mat(sum + pass);
}

}  // namespace

double displayedRmse(const cv::Mat& image, const cv::Mat& truth, const cv::Mat& mask, float exposure) {
  double squared = 0;
  std::int64_t n = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      if (!mask.at<std::uint8_t>(y, x)) continue;
      const vec3 a = rgbAt(image, x, y), t = rgbAt(truth, x, y);
      for (int c = 0; c < 3; ++c) {
        const double d = 255.0 * (linearToSrgb(exposure * a[c]) - linearToSrgb(exposure * t[c]));
        squared += d * d;
      }
      n += 3;
    }
  return n == 0 ? 0.0 : std::sqrt(squared / static_cast<double>(n));
}

ArEvaluation evaluateArComposite(const ArEvaluationOptions& o) {
  if (o.width < 1 || o.height < 1) throw InputError("AR evaluation", "size", "at least 1x1 pixels");
  if (o.truth_spp < 1 || o.method_spp < 1)
    throw InputError("AR evaluation", "spp", "at least 1 sample per pixel");
  sim::SceneDescription description = sim::loadScene(o.scene);
  if (!o.relic.empty()) description.relic = o.relic;
  description.visitors = 0;
  const sim::Museum museum(description);
  cv::Mat panorama = museum.renderPanorama(o.panorama_width, o.panorama_width / 2);
  if (o.lamp_radiance > 0.0f) {
    const vec3 lamp = glm::normalize(o.lamp_direction);
    const float cos_radius = std::cos(glm::radians(5.0f));
    for (int y = 0; y < panorama.rows; ++y)
      for (int x = 0; x < panorama.cols; ++x) {
        const vec2 uv((static_cast<float>(x) + 0.5f) / static_cast<float>(panorama.cols),
                      (static_cast<float>(y) + 0.5f) / static_cast<float>(panorama.rows));
        if (glm::dot(equirect::uvToDirection(uv), lamp) >= cos_radius)
          setRgb(panorama, x, y, vec3(o.lamp_radiance));
      }
  }
  const reflect::Environment environment(panorama);

  const float vfov = glm::radians(o.vfov_deg);
  const float hfov =
      2.0f * std::atan(std::tan(0.5f * vfov) * static_cast<float>(o.width) / static_cast<float>(o.height));
  const CameraModel camera(Intrinsics::fromFov(o.width, o.height, hfov, vfov),
                           lookAtCameraToWorld(o.eye, o.look_at));

  ArEvaluation out;
  out.exposure = description.camera.exposure;
  ar::CompositeSettings truth_settings;
  truth_settings.spp = o.truth_spp;
  truth_settings.max_bounces = o.max_bounces;
  truth_settings.seed = o.seed ^ 0x7275746Full;
  const ar::LocalScene truth_scene(trueLocalSurface(museum.hall(), o.local_radius), museum.relic(),
                                   environment);
  const ar::CompositeImage truth =
      ar::renderLocalScene(truth_scene, ar::SceneContent::kMixed, camera, truth_settings);
  const ar::CompositeImage truth_real =
      ar::renderLocalScene(truth_scene, ar::SceneContent::kReal, camera, truth_settings);
  out.truth = truth.radiance;

  // The camera: the real scene through the sensor model.
  sim::CameraSettings sensor = description.camera;
  sensor.width = o.width;
  sensor.height = o.height;
  sensor.hfov_deg = glm::degrees(hfov);
  sensor.vfov_deg = o.vfov_deg;
  sim::SensorNoise noise = description.noise;
  noise.enabled = o.sensor_noise;
  cv::Mat true_depth, cosine;
  hallDepth(museum.hall(), camera, sensor, true_depth, cosine);
  const sim::SensorOutput sensed = sim::applySensorNoise(noise, sensor, true_depth, cosine,
                                                         truth_real.radiance, o.seed, o.seed ^ 0x57a71cull);
  RgbdFrame frame;
  frame.colour = sensed.colour;
  frame.depth = sensed.depth;
  out.camera_colour = sensed.colour;

  // The region the relic changes.
  out.region = cv::Mat::zeros(o.height, o.width, CV_8UC1);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const bool relic = truth.relic_coverage.at<float>(y, x) > 0.0f;
      const float real = luminance(rgbAt(truth_real.radiance, x, y));
      const float change = std::abs(luminance(rgbAt(truth.radiance, x, y)) - real);
      out.relic_pixels += relic ? 1 : 0;
      if (relic || change > o.region_threshold * real) out.region.at<std::uint8_t>(y, x) = 255;
    }
  out.region_pixels = cv::countNonZero(out.region);
  out.shadow = out.region & (truth.relic_coverage == 0.0f);
  out.shadow_pixels = cv::countNonZero(out.shadow);
  out.relic = out.region & ~out.shadow;
  const cv::Mat everywhere(o.height, o.width, CV_8UC1, cv::Scalar(255));
  const auto errors = [&](const cv::Mat& image) {
    return ArErrors{displayedRmse(image, out.truth, out.region, out.exposure),
                    displayedRmse(image, out.truth, out.relic, out.exposure),
                    displayedRmse(image, out.truth, out.shadow, out.exposure),
                    displayedRmse(image, out.truth, everywhere, out.exposure)};
  };

  // The exact local scene path traced at the methods' samples per pixel with seeds of its own:
  // the sampling noise alone, whatever the local scene.
  {
    ar::CompositeSettings exact = truth_settings;
    exact.spp = o.method_spp;
    exact.relic_spp_factor = o.relic_spp_factor;
    exact.seed = o.seed ^ 0x65786163ull;
    out.exact_scene =
        errors(ar::renderLocalScene(truth_scene, ar::SceneContent::kMixed, camera, exact).radiance);
  }

  ar::DepthSurfaceSettings surface;
  surface.radius = o.local_radius;
  ar::CameraRealScene real = ar::realSceneFromCamera(0, camera, frame, environment, out.exposure, surface);
  const cv::Mat background = real.background;
  if (!o.estimate_albedo) std::fill(real.surface.albedo.begin(), real.surface.albedo.end(), vec3(0.5f));
  const ar::LocalScene scene(std::move(real.surface), museum.relic(), environment);
  const cv::Mat measured_depth = o.measured_real_radiance ? frame.depth : cv::Mat();

  ar::CompositeSettings delta_settings;
  delta_settings.spp = o.method_spp;
  delta_settings.max_bounces = o.max_bounces;
  delta_settings.delta_bounces = o.delta_bounces;
  delta_settings.seed = o.seed;
  delta_settings.relic_spp_factor = o.relic_spp_factor;
  const ar::ChangeRegionSettings region_settings{.exposure = out.exposure};
  const std::clock_t delta_start = std::clock();
  cv::Mat region = ar::changeRegion(scene, camera, background, region_settings);
  ar::RelicCausticSettings caustic_settings;
  caustic_settings.seed = o.seed;
  const std::optional<ar::RelicCaustic> caustic =
      ar::traceRelicCaustic(museum.relic(), environment, caustic_settings);
  out.caustic_photons = caustic ? caustic->image().traced : 0;
  if (caustic)
    ar::addCausticToRegion(*caustic, camera, background, region_settings.negligible_codes, out.exposure,
                           region);
  out.traced_pixels = cv::countNonZero(region);
  const ar::CompositeImage delta = ar::renderComposite(scene, camera, background, delta_settings, region,
                                                       measured_depth, caustic ? &*caustic : nullptr);
  out.delta.ms = cpuMsSince(delta_start);
  out.delta.spp = o.method_spp;
  out.delta.rays = delta.rays;
  out.delta_composite = delta.radiance;
  out.delta.rmse = errors(delta.radiance);
  cv::Mat relic_alone = delta.radiance.clone();
  out.truth.copyTo(relic_alone, out.shadow);
  out.delta_relic_alone = errors(relic_alone);

  // A two-pass renderer given passes until it has used at least delta path tracing's CPU time (or
  // rays): a first pass of one sample per pixel, then passes of as many samples as the rest of
  // the budget holds at the cost per sample so far (one call each, so the per-pass work outside
  // the tracing is not charged per sample), then single samples until the budget is spent.
  const auto twoPass = [&](ar::DifferentialMethod method, int relic_spp_factor, cv::Mat& composite) {
    ArMethodScore score;
    ar::CompositeSettings pass = delta_settings;
    pass.method = method;
    pass.relic_spp_factor = relic_spp_factor;
    cv::Mat sum;
    const std::clock_t start = std::clock();
    const auto spent = [&] { return o.equal_time ? score.ms : static_cast<double>(score.rays); };
    const double budget = o.equal_time ? out.delta.ms : static_cast<double>(out.delta.rays);
    do {
      const double per_sample = std::max(spent() / std::max(pass.first_sample, 1), 1e-9);
      pass.spp = pass.first_sample == 0
                     ? 1
                     : static_cast<int>(std::clamp((budget - spent()) / per_sample, 1.0, 4096.0));
      const ar::CompositeImage image =
          ar::renderComposite(scene, camera, background, pass, region, measured_depth);
      sum = accumulate(sum, image.radiance * static_cast<double>(pass.spp));
      score.rays += image.rays;
      pass.first_sample += pass.spp;
      score.ms = cpuMsSince(start);
    } while (spent() < budget);
    score.spp = pass.first_sample;
    composite = sum / static_cast<double>(score.spp);
    score.rmse = errors(composite);
    return score;
  };
  out.two_pass = twoPass(ar::DifferentialMethod::kTwoPass, 1, out.two_pass_composite);
  out.two_pass_shared =
      twoPass(ar::DifferentialMethod::kTwoPassSharedSamples, 1, out.two_pass_shared_composite);
  if (o.relic_spp_factor > 1) {
    cv::Mat unused;
    out.two_pass_split = twoPass(ar::DifferentialMethod::kTwoPass, o.relic_spp_factor, unused);
    out.two_pass_shared_split =
        twoPass(ar::DifferentialMethod::kTwoPassSharedSamples, o.relic_spp_factor, unused);
  }

  const std::clock_t filter_start = std::clock();
  out.filtered_composite =
      ar::filterChange(delta.radiance, background, delta.relic_coverage, frame.depth, {});
  out.filtered = out.delta;
  out.filtered.ms += cpuMsSince(filter_start);
  out.filtered.rmse = errors(out.filtered_composite);

  if (caustic) {
    out.caustic = cv::Mat::zeros(o.height, o.width, CV_8UC1);
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x)
        if (truth.relic_coverage.at<float>(y, x) == 0.0f &&
            luminance(rgbAt(truth.radiance, x, y)) > 1.5f * luminance(rgbAt(truth_real.radiance, x, y)))
          out.caustic.at<std::uint8_t>(y, x) = 255;
    out.caustic_pixels = cv::countNonZero(out.caustic);
    const ar::CompositeImage without =
        ar::renderComposite(scene, camera, background, delta_settings, region, measured_depth);
    out.without_light_tracer_composite =
        ar::filterChange(without.radiance, background, without.relic_coverage, frame.depth, {});
    out.without_light_tracer = errors(out.without_light_tracer_composite);
    const auto meanChange = [&](const cv::Mat& image) {
      double sum = 0;
      for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
          if (out.shadow.at<std::uint8_t>(y, x))
            sum += luminance(rgbAt(image, x, y)) - luminance(rgbAt(truth_real.radiance, x, y));
      return sum / std::max(1, out.shadow_pixels);
    };
    out.shadow_change_truth = meanChange(out.truth);
    out.shadow_change = meanChange(out.filtered_composite);
    out.shadow_change_without_light_tracer = meanChange(out.without_light_tracer_composite);
    out.caustic_rmse = displayedRmse(out.filtered_composite, out.truth, out.caustic, out.exposure);
    out.caustic_rmse_without_light_tracer =
        displayedRmse(out.without_light_tracer_composite, out.truth, out.caustic, out.exposure);
  }

  // The adversary: the relic over the camera's image, the real surfaces left as they are.
  out.no_shadow_composite = out.filtered_composite.clone();
  background.copyTo(out.no_shadow_composite, delta.relic_coverage == 0.0f);
  out.no_shadow = errors(out.no_shadow_composite);

  Model opaque = museum.relic();
  bool transmissive = false;
  for (Material& material : opaque.materials) {
    transmissive = transmissive || material.transmissive();
    material.transmission = 0.0f;
  }
  if (transmissive) {
    ar::CameraRealScene again = ar::realSceneFromCamera(0, camera, frame, environment, out.exposure, surface);
    const ar::LocalScene opaque_scene(std::move(again.surface), opaque, environment);
    const ar::CompositeImage image = ar::renderComposite(
        opaque_scene, camera, background, delta_settings,
        ar::changeRegion(opaque_scene, camera, background, region_settings), measured_depth);
    out.glass_opaque_composite =
        ar::filterChange(image.radiance, background, image.relic_coverage, frame.depth, {});
    out.glass_opaque = errors(out.glass_opaque_composite);
  }
  return out;
}

}  // namespace holo::eval
