#include "holo/reference/caustics.hpp"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/stats.hpp"
#include "holo/reference/dielectric.hpp"
#include "holo/reference/sampler.hpp"
#include "holo/reflect/caustic_tracer.hpp"
#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "surface_rays.hpp"

namespace holo::reference {

using reflect::RenderScene;
using reflect::SurfacePoint;

namespace {

// The bounding sphere of the relic's bounds.
struct BoundingSphere {
  vec3 centre;
  float radius;
};
BoundingSphere boundingSphere(const Bounds3& b) {
  return {b.center(), 0.5f * glm::length(b.hi - b.lo) * 1.0001f};
}

// The unit vector of `local` (z up) in the frame whose z is `axis`.
vec3 toWorld(const vec3& axis, const vec3& local) {
  const vec3 helper = std::abs(axis.y) < 0.9f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
  const vec3 t = glm::normalize(glm::cross(helper, axis));
  const vec3 b = glm::cross(axis, t);
  return local.x * t + local.y * b + local.z * axis;
}

}  // namespace

CausticPlan planCaustics(const RenderScene& scene, const CausticReceiver& receiver, const PointLight& light) {
  const Bounds3 bounds = scene.relicBounds();
  if (bounds.empty()) return {false, "no relic"};
  if (!reflect::relicTransmits(scene)) return {false, "the relic has no transmissive material"};
  if (bounds.lo.y <= receiver.height) return {false, "the relic is not above the receiver"};
  if (light.position.y <= receiver.height) return {false, "the light is not above the receiver"};
  if (!(receiver.half_size > 0.0f)) return {false, "the receiver has no extent"};
  return {true, "a transmissive relic above the receiver"};
}

std::vector<Photon> tracePhotons(const RenderScene& scene, const CausticReceiver& receiver,
                                 const PointLight& light, std::uint64_t first, std::uint64_t count,
                                 std::uint64_t total_count, const PhotonTracingOptions& options) {
  if (count == 0 || !planCaustics(scene, receiver, light).runs) return {};
  total_count = std::max(total_count, first + count);
  const BoundingSphere bound = boundingSphere(scene.relicBounds());
  const vec3 to_relic = bound.centre - light.position;
  const float distance = glm::length(to_relic);
  // The cone of directions the relic's bounding sphere subtends (all directions from inside it).
  const bool inside = distance <= bound.radius;
  const float cos_max =
      inside ? -1.0f
             : std::sqrt(std::max(0.0f, 1.0f - (bound.radius * bound.radius) / (distance * distance)));
  const vec3 axis = inside ? vec3(0.0f, -1.0f, 0.0f) : to_relic / distance;
  const vec3 photon_power = light.power * (0.5f * (1.0f - cos_max)) / float(total_count);
  const RayScene& relic = scene.relicOnly();

  // Fixed chunks, each its own output, joined in order: the result is independent of threading.
  constexpr std::uint64_t kChunk = 4096;
  const std::uint64_t chunks = (count + kChunk - 1) / kChunk;
  std::vector<std::vector<Photon>> kept(chunks);
  tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
    const std::uint64_t begin = first + c * kChunk, end = std::min(first + count, begin + kChunk);
    for (std::uint64_t i = begin; i < end; ++i) {
      SampleStream stream(options.seed, 0u, std::uint32_t(i));
      const vec2 u = stream.next2D();
      const float cos_theta = 1.0f - u.x * (1.0f - cos_max);
      const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
      const float phi = 2.0f * kPi * u.y;
      Ray ray{light.position,
              toWorld(axis, vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta))};
      vec3 power = photon_power;
      bool in_volume = false;
      vec3 absorption(0.0f);
      int scatterings = 0;
      for (;;) {
        const RayHit hit = relic.intersect(ray);
        const float t_receiver =
            ray.direction.y < 0.0f ? (receiver.height - ray.origin.y) / ray.direction.y : -1.0f;
        if (!hit.hit() || (t_receiver > 0.0f && t_receiver < hit.t)) {
          // Light that never met the relic is the receiver's direct light, not its caustic.
          if (scatterings == 0 || in_volume || t_receiver <= 0.0f) break;
          const vec3 p = ray.origin + t_receiver * ray.direction;
          const vec2 q = vec2(p.x, p.z) - receiver.centre;
          if (std::abs(q.x) < receiver.half_size && std::abs(q.y) < receiver.half_size && isFinite(power))
            kept[c].push_back({vec2(p.x, p.z), power});
          break;
        }
        if (in_volume) power *= reflect::transmittance(absorption, hit.t);
        if (scatterings == options.max_scatterings) break;
        const SurfacePoint surface = reflect::resolveSurface(scene, relic, ray, hit, 0.0f);
        if (!isFinite(surface.normal) || !isFinite(surface.position)) break;
        const bool front = meetsFrontFace(relic, hit, ray.direction);
        const MaterialBsdf bsdf(surface.material, surface.normal, front, surface.clearcoat_normal);
        const auto bs = bsdf.sample(-ray.direction, stream.next3D());
        if (!bs) break;
        ++scatterings;
        power *= bs->weight * surface.occlusion;
        if (!(power.x > 0.0f || power.y > 0.0f || power.z > 0.0f)) break;
        if (bs->transmitted && !bsdf.thinWalled()) {
          in_volume = front;
          absorption = in_volume ? reflect::attenuationCoefficient(surface.material.attenuation_colour,
                                                                   surface.material.attenuation_distance)
                                 : vec3(0.0f);
        }
        ray = spawnRay(surface.position, hit.geometric_normal, bs->wi);
      }
    }
  });
  std::vector<Photon> out;
  for (const auto& k : kept) out.insert(out.end(), k.begin(), k.end());
  static auto& traced = stats::counter("Caustics/Photons traced");
  static auto& stored = stats::counter("Caustics/Photons stored");
  traced.fetch_add(std::int64_t(count), std::memory_order_relaxed);
  stored.fetch_add(std::int64_t(out.size()), std::memory_order_relaxed);
  return out;
}

vec2 ReceiverImage::cellCentre(int column, int row) const {
  const float cell = cellSize();
  return receiver.centre - vec2(receiver.half_size) + cell * (vec2(float(column), float(row)) + 0.5f);
}

ReceiverImage photonMapEstimate(const std::vector<Photon>& photons, const CausticReceiver& receiver,
                                int resolution, float radius) {
  ReceiverImage image{receiver, std::max(1, resolution), {}};
  const int n = image.resolution;
  image.irradiance = cv::Mat(n, n, CV_32FC3, cv::Scalar::all(0));
  radius = std::max(radius, 1e-6f);
  // Photons hashed into square buckets of the kernel's radius: a cell gathers from 3x3 of them.
  const vec2 lo = receiver.centre - vec2(receiver.half_size + radius);
  const int buckets = std::max(1, int(std::ceil(2.0f * (receiver.half_size + radius) / radius)));
  std::vector<std::vector<std::uint32_t>> grid(std::size_t(buckets) * std::size_t(buckets));
  const auto bucketOf = [&](float v) { return std::clamp(int((v) / radius), 0, buckets - 1); };
  for (std::size_t i = 0; i < photons.size(); ++i) {
    const vec2 q = photons[i].position - lo;
    grid[std::size_t(bucketOf(q.y)) * buckets + std::size_t(bucketOf(q.x))].push_back(std::uint32_t(i));
  }
  // Epanechnikov kernel: (2 / (pi r^2)) (1 - d^2 / r^2), integrating to 1 over the disc.
  const double norm = 2.0 / (double(kPi) * double(radius) * double(radius));
  tbb::parallel_for(0, n, [&](int row) {
    auto* out = image.irradiance.ptr<cv::Vec3f>(row);
    for (int column = 0; column < n; ++column) {
      const vec2 x = image.cellCentre(column, row);
      const int bx = bucketOf(x.x - lo.x), by = bucketOf(x.y - lo.y);
      glm::dvec3 sum(0.0);
      for (int gy = std::max(0, by - 1); gy <= std::min(buckets - 1, by + 1); ++gy) {
        for (int gx = std::max(0, bx - 1); gx <= std::min(buckets - 1, bx + 1); ++gx) {
          for (std::uint32_t i : grid[std::size_t(gy) * buckets + std::size_t(gx)]) {
            const vec2 d = photons[i].position - x;
            const float d2 = glm::dot(d, d) / (radius * radius);
            if (d2 < 1.0f) sum += glm::dvec3(photons[i].power) * double(1.0f - d2);
          }
        }
      }
      sum *= norm;
      out[column] = cv::Vec3f(float(sum.z), float(sum.y), float(sum.x));
    }
  });
  return image;
}

LightTracerImage::LightTracerImage(const CausticReceiver& receiver, int resolution)
    : receiver_(receiver),
      resolution_(std::max(1, resolution)),
      power_(std::size_t(resolution_) * std::size_t(resolution_), glm::dvec3(0.0)) {}

void LightTracerImage::addPhotons(const std::vector<Photon>& photons) {
  const float cell = 2.0f * receiver_.half_size / float(resolution_);
  const vec2 lo = receiver_.centre - vec2(receiver_.half_size);
  for (const Photon& p : photons) {
    const vec2 q = (p.position - lo) / cell;
    const int x = std::clamp(int(q.x), 0, resolution_ - 1), y = std::clamp(int(q.y), 0, resolution_ - 1);
    power_[std::size_t(y) * resolution_ + std::size_t(x)] += glm::dvec3(p.power);
  }
}

ReceiverImage LightTracerImage::image() const {
  ReceiverImage image{receiver_, resolution_, cv::Mat(resolution_, resolution_, CV_32FC3)};
  const double area = double(image.cellSize()) * double(image.cellSize());
  for (int y = 0; y < resolution_; ++y) {
    for (int x = 0; x < resolution_; ++x) {
      const glm::dvec3 e = power_[std::size_t(y) * resolution_ + std::size_t(x)] / area;
      image.irradiance.at<cv::Vec3f>(y, x) = cv::Vec3f(float(e.z), float(e.y), float(e.x));
    }
  }
  return image;
}

namespace {
cv::Mat luminanceOf(const cv::Mat& bgr) {
  cv::Mat lum(bgr.size(), CV_64F);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3f v = bgr.at<cv::Vec3f>(y, x);
      lum.at<double>(y, x) = double(luminance(vec3(v[2], v[1], v[0])));
    }
  return lum;
}
}  // namespace

vec2 causticPeak(const ReceiverImage& image, float window) {
  const cv::Mat lum = luminanceOf(image.irradiance);
  cv::Mat smooth;
  cv::blur(lum, smooth, cv::Size(3, 3), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::Point brightest;
  cv::minMaxLoc(smooth, nullptr, nullptr, nullptr, &brightest);
  const vec2 centre = image.cellCentre(brightest.x, brightest.y);
  glm::dvec2 sum(0.0);
  double weight = 0.0;
  for (int y = 0; y < lum.rows; ++y)
    for (int x = 0; x < lum.cols; ++x) {
      const vec2 c = image.cellCentre(x, y);
      if (glm::length(c - centre) > window) continue;
      sum += glm::dvec2(c) * lum.at<double>(y, x);
      weight += lum.at<double>(y, x);
    }
  return weight > 0.0 ? vec2(sum / weight) : centre;
}

double causticPower(const ReceiverImage& image, const vec2& centre, float radius) {
  const cv::Mat lum = luminanceOf(image.irradiance);
  const double area = double(image.cellSize()) * double(image.cellSize());
  double power = 0.0;
  for (int y = 0; y < lum.rows; ++y)
    for (int x = 0; x < lum.cols; ++x)
      if (glm::length(image.cellCentre(x, y) - centre) <= radius) power += lum.at<double>(y, x) * area;
  return power;
}

}  // namespace holo::reference
