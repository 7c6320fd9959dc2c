#include "holo/eval/plinth_evaluation.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/eval/caustic_evaluation.hpp"
#include "holo/eval/methods.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"

namespace holo::eval {

namespace {

cv::Mat lampPanorama(const PlinthEvaluationOptions& o) {
  const int w = 1024, h = 512;
  const float a = glm::radians(o.lamp_angle_deg);
  const vec3 lamp(std::sin(a), std::cos(a), 0.0f);
  const float cos_radius = std::cos(glm::radians(o.lamp_radius_deg));
  cv::Mat pano(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const vec3 d =
          equirect::uvToDirection(vec2((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)));
      const float L = glm::dot(d, lamp) >= cos_radius ? o.lamp_radiance : o.sky_radiance;
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(L, L, L);
    }
  return pano;
}

std::uint64_t counterOf(const reflect::FrameResult& r, bool stored) {
  return stored ? r.caustic_photons_stored : r.caustic_photons_traced;
}

struct Ours {
  cv::Mat image;
  reflect::FrameResult result;
  double ms = 0, caustic_ms = 0;
};

Ours renderOurs(const ReflectionScene& scene, const reflect::PrefilteredIbl& ibl, const CameraModel& camera,
                const PlinthEvaluationOptions& o, bool caustic, bool shadow) {
  const reflect::RenderScene rs(scene.relic, {});
  reflect::TracerSettings t;
  t.plinth = scene.plinth;
  t.caustic_photons = o.caustic_photons;
  t.evaluation.plinth_caustic = caustic;
  t.evaluation.plinth_shadow = shadow;
  reflect::FrameRenderer renderer(rs, ibl, t);
  const depthfilter::ForegroundCloud nobody;
  Ours out;
  out.result = renderer.render(nobody, {}, {camera});
  for (const reflect::PassTiming& p : out.result.frame_timings) {
    out.ms += p.ms;
    if (p.pass == reflect::Pass::Caustics) out.caustic_ms += p.ms;
  }
  for (const reflect::PassTiming& p : out.result.views.at(0).timings) out.ms += p.ms;
  out.image = out.result.views.at(0).hdr;
  return out;
}

double lum(const cv::Vec3f& v) {
  return double(luminance(vec3(v[2], v[1], v[0])));
}

double relativeRmse(const cv::Mat& image, const cv::Mat& truth, const cv::Mat& mask) {
  double sq = 0, sum = 0;
  int n = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      if (!mask.at<std::uint8_t>(y, x)) continue;
      const double t = lum(truth.at<cv::Vec3f>(y, x)), e = lum(image.at<cv::Vec3f>(y, x)) - t;
      sq += e * e;
      sum += t;
      ++n;
    }
  return n > 0 && sum > 0 ? std::sqrt(sq / n) / (sum / n) : 0.0;
}

}  // namespace

ReflectionScene plinthScene(const PlinthEvaluationOptions& o) {
  ReflectionScene s;
  s.scene_name = "plinth";
  s.relic_name = o.relic;
  PlinthSettings plinth;
  plinth.half_width = 0.15f;
  plinth.height = 0.1f;
  plinth.albedo = vec3(0.7f);
  if (o.relic == "glass-sphere") {
    const CausticScene caustic;
    s.relic = causticSphere(caustic, false);
    plinth.gap = caustic.centre_height - caustic.radius;
  } else {
    s.relic = relics::makeRelic(o.relic);
    relics::fitOnPedestal(s.relic);
  }
  s.plinth = plinth;
  s.panorama = lampPanorama(o);
  return s;
}

CameraModel plinthCamera(const ReflectionScene& scene, int size) {
  const Bounds3 b = scene.relic.bounds();
  const PlinthBox box = placePlinth(*scene.plinth, b);
  const vec3 target(box.centre.x, 0.5f * (box.top + b.hi.y) - 0.25f * (b.hi.y - box.top), box.centre.y);
  const float reach = std::max(box.half_width, 0.5f * (b.hi.y - box.top));
  const vec3 eye = target + reach * vec3(0.0f, 1.6f, 2.6f);
  return reflect::lookAtCamera(eye, target, 40.0f, size, size);
}

PlinthEvaluation evaluatePlinth(const PlinthEvaluationOptions& o) {
  const ReflectionScene scene = plinthScene(o);
  const CameraModel camera = plinthCamera(scene, o.size);
  MethodSettings settings;
  settings.spp = o.truth_spp;
  settings.seed = o.seed;
  settings.with_visitors = false;
  const auto ibl = staticIbl(scene, settings);
  PlinthEvaluation e;
  e.truth = renderMethod("gt", scene, camera, settings, true).image;
  const Ours ours = renderOurs(scene, *ibl, camera, o, true, true);
  e.ours = ours.image;
  e.ours_ms = ours.ms;
  e.caustic_ms = ours.caustic_ms;
  e.photons_traced = counterOf(ours.result, false);
  e.photons_stored = counterOf(ours.result, true);
  e.ours_no_caustic = renderOurs(scene, *ibl, camera, o, false, true).image;
  e.ours_unshadowed = renderOurs(scene, *ibl, camera, o, false, false).image;

  // The plinth's pixels: the primary ray meets the plinth and not the relic before it.
  const reflect::RenderScene rs(scene.relic, {});
  const PlinthBox box = placePlinth(*scene.plinth, scene.relic.bounds());
  e.plinth_mask = cv::Mat::zeros(o.size, o.size, CV_8U);
  cv::Mat caustic_mask = cv::Mat::zeros(o.size, o.size, CV_8U);
  for (int y = 0; y < o.size; ++y)
    for (int x = 0; x < o.size; ++x) {
      const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(y)));
      const auto plinth = intersectPlinth(box, ray);
      if (!plinth) continue;
      const RayHit relic = rs.relicOnly().intersect(ray);
      if (relic.hit() && relic.t < plinth->t) continue;
      e.plinth_mask.at<std::uint8_t>(y, x) = 255;
      ++e.plinth_pixels;
      if (lum(e.truth.at<cv::Vec3f>(y, x)) > 1.1 * lum(e.ours_unshadowed.at<cv::Vec3f>(y, x))) {
        caustic_mask.at<std::uint8_t>(y, x) = 255;
        ++e.caustic_pixels;
      }
    }
  e.error = relativeRmse(e.ours, e.truth, e.plinth_mask);
  e.error_no_caustic = relativeRmse(e.ours_no_caustic, e.truth, e.plinth_mask);
  e.error_unshadowed = relativeRmse(e.ours_unshadowed, e.truth, e.plinth_mask);
  e.caustic_error = relativeRmse(e.ours, e.truth, caustic_mask);
  e.caustic_error_no_caustic = relativeRmse(e.ours_no_caustic, e.truth, caustic_mask);
  return e;
}

}  // namespace holo::eval
