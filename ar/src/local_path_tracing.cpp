#include "holo/ar/local_path_tracing.hpp"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/optics.hpp"
#include "random.hpp"

namespace holo::ar {
namespace {

// Reflections and refractions at the relic's glass a path follows, apart from its scatterings
// (a ray through a thick-walled vase crosses four interfaces).
constexpr int kMaxGlassEvents = 16;

bool positive(const vec3& v) {
  return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f;
}

// What the camera measured of the real surfaces: its image as radiance and its depth. A real
// surface point the camera sees (the same side of the surface, its depth within kSeenDepthTolerance
// of the camera's at its pixel) leaves the camera's radiance at that pixel towards every direction
// (the local scene is Lambertian).
struct CameraMeasurement {
  const CameraModel& camera;
  const cv::Mat& radiance;  // CV_32FC3 linear BGR
  const cv::Mat& depth;     // CV_32FC1 camera-frame z, 0 = invalid

  static constexpr float kSeenDepthTolerance = 0.03f;  // relative

  // The radiance the real scene sends from `hit` (met along `ray`) towards anywhere, where the
  // camera sees that point.
  std::optional<vec3> radianceAt(const Ray& ray, const RayHit& hit) const {
    const vec3 p = ray.origin + hit.t * ray.direction;
    float z = 0.0f;
    const std::optional<vec2> pixel = camera.project(p, &z);
    if (!pixel) return std::nullopt;
    const int x = static_cast<int>(std::lround(pixel->x)), y = static_cast<int>(std::lround(pixel->y));
    if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return std::nullopt;
    const float seen = depth.at<float>(y, x);
    if (!(seen > 0.0f) || std::abs(z - seen) > kSeenDepthTolerance * seen) return std::nullopt;
    const vec3& n = hit.geometric_normal;
    if (glm::dot(n, ray.direction) * glm::dot(n, p - camera.position()) <= 0.0f) return std::nullopt;
    return rgbAt(radiance, x, y);
  }
};

// The path tracing of one scene content, counting its rays. With a camera measurement, a path
// that meets a real surface the camera sees after the relic takes that surface's radiance as the
// camera's plus its change (delta path tracing there, `delta_levels` levels) instead of tracing it.
// With a caustic, a real surface's change on the receiver takes the relic's caustic from it.
class Tracer {
 public:
  Tracer(const LocalScene& scene, std::int64_t& rays, const CameraMeasurement* measured = nullptr,
         int delta_levels = 1, const RelicCaustic* caustic = nullptr)
      : scene_(scene), rays_(rays), measured_(measured), delta_levels_(delta_levels), caustic_(caustic) {}

  // Radiance leaving `hit` back along `ray`, by a path of at most `scatterings` scatterings on
  // opaque lobes and at most kMaxGlassEvents on the relic's glass. `caustic_elsewhere`: the light
  // that reaches the panorama through the glass alone, before any scattering, is left out (the
  // caustic's light tracer carries it).
  vec3 fromHit(SceneContent content, Ray ray, RayHit hit, Random& random, int scatterings,
               bool caustic_elsewhere = false) const {
    const reflect::Environment& environment = scene_.environment();
    vec3 radiance(0.0f), throughput(1.0f);
    int glass_events = 0;
    for (int k = 0; k < scatterings;) {
      if (measured_ && !scene_.isRelic(hit.geometry)) {
        if (const std::optional<vec3> seen = measured_->radianceAt(ray, hit)) {
          const vec3 change = content == SceneContent::kMixed
                                  ? delta(ray, hit, random, scatterings - k, delta_levels_)
                                  : vec3(0.0f);
          radiance += throughput * (*seen + change);
          break;
        }
      }
      if (const RelicGlass* glass = scene_.glassAt(hit)) {
        random.uniform2();  // keep the sample sequence aligned: no light sampling at a smooth interface
        const vec3 u = random.uniform3();
        if (u.z < glass->transmission) {
          if (++glass_events > kMaxGlassEvents) break;
          const vec3 direction = crossGlass(*glass, ray, hit, u.x, throughput);
          const Ray next{scene_.offsetOrigin(ray, hit, direction), direction};
          ++rays_;
          const RayHit next_hit = scene_.intersect(content, next);
          if (!next_hit.hit()) {  // a delta event: no light sample could have found this
            if (!(caustic_elsewhere && k == 0)) radiance += throughput * environment.radiance(direction);
            break;
          }
          ray = next;
          hit = next_hit;
          continue;
        }
      }
      ++k;
      const reflect::Bsdf bsdf = scene_.bsdfAt(ray, hit);
      const vec3 wo = -ray.direction;
      if (!bsdf.mirror()) {
        const reflect::EnvironmentSample light = environment.sample(random.uniform2());
        if (light.pdf > 0.0f) {
          const vec3 f = bsdf.eval(wo, light.direction);
          if (positive(f)) {
            ++rays_;
            if (!scene_.occluded(content,
                                 {scene_.offsetOrigin(ray, hit, light.direction), light.direction})) {
              const float bsdf_pdf = bsdf.pdf(wo, light.direction);
              radiance += throughput * f * light.radiance / (light.pdf + bsdf_pdf);
            }
          }
        }
      } else {
        random.uniform2();  // keep the sample sequence aligned
      }
      const auto scattered = bsdf.sample(wo, random.uniform3());
      if (!scattered || !positive(scattered->weight)) break;
      throughput *= scattered->weight;
      const Ray next{scene_.offsetOrigin(ray, hit, scattered->wi), scattered->wi};
      ++rays_;
      const RayHit next_hit = scene_.intersect(content, next);
      if (!next_hit.hit()) {
        const float weight =
            scattered->delta ? 1.0f : scattered->pdf / (scattered->pdf + environment.pdf(scattered->wi));
        radiance += throughput * environment.radiance(scattered->wi) * weight;
        break;
      }
      ray = next;
      hit = next_hit;
    }
    return radiance;
  }

  // The direction a path takes at the relic's smooth glass (reflected with the Fresnel
  // reflectance's probability, else refracted or, thin-walled, passed straight), `throughput`
  // multiplied by what the glass keeps: the tint on entering, Beer-Lambert absorption over the
  // segment inside that ends here.
  vec3 crossGlass(const RelicGlass& glass, const Ray& ray, const RayHit& hit, float u,
                  vec3& throughput) const {
    const bool front = scene_.frontFace(ray, hit);
    vec3 n = scene_.shadingNormal(hit, ray.direction);
    if (glm::dot(n, ray.direction) > 0.0f) n = -n;
    const float cos_i = std::clamp(-glm::dot(ray.direction, n), 0.0f, 1.0f);
    if (glass.thin_walled) {
      if (u < reflect::fresnelDielectric(cos_i, glass.ior)) return glm::reflect(ray.direction, n);
      throughput *= glass.tint;
      return ray.direction;
    }
    if (!front) throughput *= reflect::transmittance(glass.sigma, hit.t);
    const float eta = front ? glass.ior : 1.0f / glass.ior;
    if (u < reflect::fresnelDielectric(cos_i, eta)) return glm::reflect(ray.direction, n);
    if (front) throughput *= glass.tint;
    return reflect::refractIncident(ray.direction, n, eta);
  }

  // Radiance arriving along `ray` in the scene `content`.
  vec3 along(SceneContent content, const Ray& ray, Random& random, int scatterings, bool* met_relic) const {
    ++rays_;
    const RayHit hit = scene_.intersect(content, ray);
    if (met_relic) *met_relic = hit.hit() && scene_.isRelic(hit.geometry);
    if (!hit.hit()) return scene_.environment().radiance(ray.direction);
    return fromHit(content, ray, hit, random, scatterings);
  }

  // Delta path tracing at a real surface's hit (the mixed scene's radiance leaving it minus the
  // real scene's): `scatterings` left for paths from here, `levels` real levels still traced.
  vec3 delta(const Ray& ray, const RayHit& hit, Random& random, int scatterings, int levels) const {
    const reflect::Environment& environment = scene_.environment();
    constexpr SceneContent kMixed = SceneContent::kMixed, kReal = SceneContent::kReal;
    const reflect::Bsdf bsdf = scene_.bsdfAt(ray, hit);
    const vec3 wo = -ray.direction;
    vec3 change(0.0f);
    // The light the relic's glass focuses here, from the caustic's light tracer.
    const vec3 p = ray.origin + hit.t * ray.direction;
    const bool caustic_here = caustic_ && caustic_->onReceiver(p, scene_.shadingNormal(hit, ray.direction));
    if (caustic_here) change += scene_.realAlbedo(hit) * (1.0f / kPi) * caustic_->irradianceAt(p);
    // The panorama's light the relic blocks, by environment sampling.
    const reflect::EnvironmentSample light = environment.sample(random.uniform2());
    if (light.pdf > 0.0f) {
      const vec3 f = bsdf.eval(wo, light.direction);
      const Ray shadow{scene_.offsetOrigin(ray, hit, light.direction), light.direction};
      // A shadow ray that misses the relic's bounding sphere cannot be blocked by it: no change.
      if (positive(f) && scene_.relicBounds().mayHit(shadow)) {
        ++rays_;
        const RayHit blocker = scene_.intersect(kMixed, shadow);
        if (blocker.hit() && scene_.isRelic(blocker.geometry)) {
          ++rays_;
          if (!scene_.occluded(kReal, shadow))
            change -= f * light.radiance / (light.pdf + bsdf.pdf(wo, light.direction));
        }
      }
    }
    // By BSDF sampling: what the relic brings instead of what it hides, or a real surface's change.
    const auto scattered = bsdf.sample(wo, random.uniform3());
    if (!scattered || !positive(scattered->weight)) return change;
    const Ray next{scene_.offsetOrigin(ray, hit, scattered->wi), scattered->wi};
    ++rays_;
    const RayHit next_hit = scene_.intersect(kMixed, next);
    if (!next_hit.hit()) return change;  // the panorama, in both scenes
    if (scene_.isRelic(next_hit.geometry)) {
      const vec3 added = scatterings > 1 ? fromHit(SceneContent::kMixed, next, next_hit, random,
                                                   scatterings - 1, caustic_here)
                                         : vec3(0.0f);
      ++rays_;
      const RayHit hidden = scene_.intersect(kReal, next);
      vec3 blocked(0.0f);
      if (!hidden.hit()) {
        const float weight =
            scattered->delta ? 1.0f : scattered->pdf / (scattered->pdf + environment.pdf(scattered->wi));
        blocked = environment.radiance(scattered->wi) * weight;
      } else if (scatterings > 1) {
        blocked = fromHit(SceneContent::kReal, next, hidden, random, scatterings - 1);
      }
      return change + scattered->weight * (added - blocked);
    }
    if (levels > 1 && scatterings > 1)
      change += scattered->weight * delta(next, next_hit, random, scatterings - 1, levels - 1);
    return change;
  }

 private:
  const LocalScene& scene_;
  std::int64_t& rays_;
  const CameraMeasurement* measured_;
  int delta_levels_;
  const RelicCaustic* caustic_;
};

void checkSettings(const CameraModel& camera, const CompositeSettings& s) {
  if (camera.width() <= 0 || camera.height() <= 0)
    throw InputError("AR composite", "camera", "an image size of at least 1x1 pixels");
  if (s.spp < 1) throw InputError("AR composite", "spp", "at least 1 sample per pixel");
  if (s.relic_spp_factor < 1)
    throw InputError("AR composite", "relic_spp_factor", "at least 1 (the relic's pixels' samples per spp)");
  if (s.max_bounces < 1) throw InputError("AR composite", "max_bounces", "at least 1 scattering");
  if (s.delta_bounces < 1) throw InputError("AR composite", "delta_bounces", "at least 1 level");
}

// CV_8UC1 of the camera's size: 255 where the relic is seen (the pixel's centre ray or one of
// its 8 neighbours' meets the relic first), within `region` (empty: every pixel). One ray per
// pixel, counted in `rays`; an unbiased choice of where to sample more (the pixel samples
// themselves do not decide it).
cv::Mat relicPixels(const LocalScene& scene, const CameraModel& camera, const cv::Mat& region,
                    std::int64_t& rays) {
  const int w = camera.width(), h = camera.height();
  cv::Mat centre_on_relic(h, w, CV_8UC1, cv::Scalar(0));
  tbb::combinable<std::int64_t> cast([] { return std::int64_t{0}; });
  tbb::parallel_for(0, h, [&](int y) {
    std::int64_t& local = cast.local();
    for (int x = 0; x < w; ++x) {
      if (!region.empty() && region.at<std::uint8_t>(y, x) == 0) continue;
      ++local;
      const RayHit hit =
          scene.intersect(SceneContent::kMixed, camera.ray({static_cast<float>(x), static_cast<float>(y)}));
      if (hit.hit() && scene.isRelic(hit.geometry)) centre_on_relic.at<std::uint8_t>(y, x) = 255;
    }
  });
  rays += cast.combine(std::plus<>());
  cv::Mat seen;
  cv::dilate(centre_on_relic, seen, cv::Mat::ones(3, 3, CV_8UC1));
  return seen;
}

// Runs sample(x, y, index, random, coverage) for every pixel sample over oneTBB tiles; a pixel
// outside `region` (CV_8UC1 0; an empty region holds every pixel) is `outside`'s pixel, untraced.
// A pixel in `more` (CV_8UC1 255; empty: none) takes s.relic_spp_factor x s.spp samples.
template <typename PixelSample>
CompositeImage renderSamples(const CameraModel& camera, const CompositeSettings& s, const cv::Mat& region,
                             const cv::Mat& outside, const cv::Mat& more, std::int64_t rays_before,
                             PixelSample&& sample) {
  const int w = camera.width(), h = camera.height();
  CompositeImage out;
  out.radiance = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
  out.relic_coverage = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
  tbb::combinable<std::int64_t> rays([] { return std::int64_t{0}; });
  tbb::parallel_for(tbb::blocked_range2d<int>(0, h, 8, 0, w, 8), [&](const tbb::blocked_range2d<int>& r) {
    std::int64_t& local_rays = rays.local();
    for (int y = r.rows().begin(); y != r.rows().end(); ++y)
      for (int x = r.cols().begin(); x != r.cols().end(); ++x) {
        if (!region.empty() && region.at<std::uint8_t>(y, x) == 0) {
          setRgb(out.radiance, x, y, rgbAt(outside, x, y));
          continue;
        }
        const int factor = !more.empty() && more.at<std::uint8_t>(y, x) ? s.relic_spp_factor : 1;
        const int samples = factor * s.spp;
        glm::dvec3 sum(0.0);
        int on_relic = 0;
        for (int i = 0; i < samples; ++i) {
          const int index = factor * s.first_sample + i;
          Random random(s.seed, static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + x,
                        static_cast<std::uint64_t>(index));
          const vec2 jitter = random.uniform2();
          const Ray ray =
              camera.ray({static_cast<float>(x) + jitter.x - 0.5f, static_cast<float>(y) + jitter.y - 0.5f});
          bool relic = false;
          const vec3 value = sample(x, y, ray, random, relic, local_rays);
          if (std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z))
            sum += glm::dvec3(value);
          on_relic += relic ? 1 : 0;
        }
        setRgb(out.radiance, x, y, vec3(sum / static_cast<double>(samples)));
        out.relic_coverage.at<float>(y, x) = static_cast<float>(on_relic) / static_cast<float>(samples);
      }
  });
  out.rays = rays_before + rays.combine(std::plus<>());
  return out;
}

}  // namespace

CompositeImage renderComposite(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                               const CompositeSettings& s, const cv::Mat& region, const cv::Mat& depth,
                               const RelicCaustic* caustic) {
  checkSettings(camera, s);
  if (background.type() != CV_32FC3 || background.cols != camera.width() ||
      background.rows != camera.height())
    throw InputError("AR composite", "background",
                     "the camera's image as linear radiance (CV_32FC3) of the camera's size " +
                         std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  if (!region.empty() && (region.type() != CV_8UC1 || region.size() != background.size()))
    throw InputError("AR composite", "region", "CV_8UC1 of the camera's size (or empty: every pixel)");
  if (!depth.empty() && (depth.type() != CV_32FC1 || depth.size() != background.size()))
    throw InputError("AR composite", "depth", "CV_32FC1 metres of the camera's size (or empty: none)");
  const CameraMeasurement measurement{camera, background, depth};
  const CameraMeasurement* measured = depth.empty() ? nullptr : &measurement;
  std::int64_t pilot_rays = 0;
  const cv::Mat more = s.relic_spp_factor > 1 ? relicPixels(scene, camera, region, pilot_rays) : cv::Mat();
  return renderSamples(
      camera, s, region, background, more, pilot_rays,
      [&](int x, int y, const Ray& ray, Random& random, bool& relic, std::int64_t& rays) {
        const Tracer tracer(scene, rays, nullptr, 1, caustic);
        const vec3 seen = rgbAt(background, x, y);
        ++rays;
        const RayHit hit = scene.intersect(SceneContent::kMixed, ray);
        if (!hit.hit()) return seen;
        if (scene.isRelic(hit.geometry)) {
          relic = true;
          return Tracer(scene, rays, measured, s.delta_bounces, caustic)
              .fromHit(SceneContent::kMixed, ray, hit, random, s.max_bounces);
        }
        if (s.method == DifferentialMethod::kDeltaPathTracing)
          return seen + tracer.delta(ray, hit, random, s.max_bounces, s.delta_bounces);
        // The real scene's path: from the same random numbers as the mixed scene's (shared
        // samples), or a render of its own with its own samples. Its primary hit is the mixed
        // scene's (a real surface the relic does not hide), so it is not cast again.
        Random without_random = random;
        const vec3 with_relic = tracer.fromHit(SceneContent::kMixed, ray, hit, random, s.max_bounces);
        if (s.method == DifferentialMethod::kTwoPass)
          without_random =
              Random(~s.seed, static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(camera.width()) + x,
                     static_cast<std::uint64_t>(random.next()));
        const vec3 without = tracer.fromHit(SceneContent::kReal, ray, hit, without_random, s.max_bounces);
        return seen + with_relic - without;
      });
}

CompositeImage renderLocalScene(const LocalScene& scene, SceneContent content, const CameraModel& camera,
                                const CompositeSettings& s) {
  checkSettings(camera, s);
  std::int64_t pilot_rays = 0;
  const cv::Mat more = s.relic_spp_factor > 1 ? relicPixels(scene, camera, cv::Mat(), pilot_rays) : cv::Mat();
  return renderSamples(camera, s, cv::Mat(), cv::Mat(), more, pilot_rays,
                       [&](int, int, const Ray& ray, Random& random, bool& relic, std::int64_t& rays) {
                         return Tracer(scene, rays).along(content, ray, random, s.max_bounces, &relic);
                       });
}

}  // namespace holo::ar
