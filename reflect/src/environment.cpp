#include "holo/reflect/environment.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/stats.hpp"

namespace holo::reflect {

double Environment::pixelSolidAngle(int y, int width, int height) {
  const double theta0 = double(y) / height * double(kPi);
  const double theta1 = double(y + 1) / height * double(kPi);
  return (2.0 * double(kPi) / width) * (std::cos(theta0) - std::cos(theta1));
}

namespace {

// Distance along unit `direction` from `origin` (inside the sphere) to the sphere; negative when
// the origin is not inside it.
float exitDistance(const PanoramaProxy& proxy, const vec3& origin, const vec3& direction) {
  const vec3 m = origin - proxy.centre;
  const float c = glm::dot(m, m) - proxy.radius * proxy.radius;
  if (!(c < 0.0f)) return -1.0f;
  const float b = glm::dot(m, direction);
  return -b + std::sqrt(b * b - c);
}

}  // namespace

vec3 PanoramaProxy::lookupDirection(const vec3& origin, const vec3& direction) const {
  if (infinite()) return direction;
  const float t = exitDistance(*this, origin, direction);
  if (!(t > 0.0f)) return direction;
  return glm::normalize(origin + t * direction - centre);
}

float PanoramaProxy::solidAngleRatio(const vec3& origin, const vec3& direction) const {
  if (infinite()) return 1.0f;
  const float t = exitDistance(*this, origin, direction);
  if (!(t > 0.0f)) return 1.0f;
  const vec3 normal = (origin + t * direction - centre) / radius;
  const float cosine = std::max(glm::dot(normal, direction), 1e-6f);
  return t * t / (radius * radius * cosine);
}

Environment::Environment(const cv::Mat& panorama, float yaw, PanoramaProxy proxy) : yaw_(yaw), proxy_(proxy) {
  if (panorama.empty() || panorama.type() != CV_32FC3)
    throw InputError("", "panorama", "a non-empty CV_32FC3 linear BGR image");
  if (!isFinite(proxy_.centre) || !(proxy_.radius > 0.0f))
    throw InputError("", "panorama proxy", "a finite centre and a radius > 0 metres (infinite: no parallax)");
  panorama_ = panorama.clone();
  repaired_ = sanitizeRadiance(panorama_);
  if (repaired_.total() > 0) {
    stats::add("Reflect/Environment pixels repaired", repaired_.total());
  }
  const int w = panorama_.cols, h = panorama_.rows;
  std::vector<double> weights(static_cast<std::size_t>(w) * h);
  row_solid_angle_.resize(static_cast<std::size_t>(h));
  glm::dvec3 integral(0.0);
  std::uint64_t hash = 1469598103934665603ull ^ std::uint64_t(std::bit_cast<std::uint32_t>(yaw));
  for (int y = 0; y < h; ++y) {
    const double omega = pixelSolidAngle(y, w, h);
    row_solid_angle_[y] = omega;
    const auto* row = panorama_.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      const cv::Vec3f& p = row[x];
      weights[static_cast<std::size_t>(y) * w + x] = double(std::max({p[0], p[1], p[2]})) * omega;
      integral += glm::dvec3(p[2], p[1], p[0]) * omega;
      for (int c = 0; c < 3; ++c) {
        hash ^= std::bit_cast<std::uint32_t>(p[c]);
        hash *= 1099511628211ull;
      }
    }
  }
  for (const float f : {proxy_.centre.x, proxy_.centre.y, proxy_.centre.z, proxy_.radius}) {
    hash ^= std::bit_cast<std::uint32_t>(f);
    hash *= 1099511628211ull;
  }
  hash_ = hash ^ (std::uint64_t(w) << 32) ^ std::uint64_t(h);
  integral_ = vec3(integral);
  distribution_ = Distribution2D(weights, w, h);
}

Environment Environment::uniform(const vec3& radiance, int width, int height) {
  cv::Mat pano(height, width, CV_32FC3, cv::Scalar(radiance.b, radiance.g, radiance.r));
  return Environment(pano);
}

ivec2 Environment::pixelOf(const vec3& direction) const {
  const vec2 uv = equirect::directionToUv(direction, yaw_);
  const int w = panorama_.cols, h = panorama_.rows;
  return {std::clamp(static_cast<int>(uv.x * float(w)), 0, w - 1),
          std::clamp(static_cast<int>(uv.y * float(h)), 0, h - 1)};
}

vec3 Environment::radiance(const vec3& direction) const {
  if (panorama_.empty() || !isFinite(direction)) return vec3(0.0f);
  const ivec2 p = pixelOf(direction);
  return rgbAt(panorama_, p.x, p.y);
}

float Environment::pdf(const vec3& direction) const {
  if (black() || !isFinite(direction)) return 0.0f;
  const ivec2 p = pixelOf(direction);
  return float(distribution_.probability(p.x, p.y) / row_solid_angle_[p.y]);
}

EnvironmentSample Environment::sample(const vec2& u) const {
  EnvironmentSample s;
  if (black()) return s;
  const Distribution2D::Sample cell = distribution_.sample(u);
  if (!(cell.probability > 0)) return s;
  const int w = panorama_.cols, h = panorama_.rows;
  // Uniform in solid angle inside the pixel: longitude linear, cos(colatitude) linear.
  const double cos0 = std::cos(double(cell.y) / h * double(kPi));
  const double cos1 = std::cos(double(cell.y + 1) / h * double(kPi));
  const double cos_theta = cos0 + (cos1 - cos0) * double(cell.within.y);
  const float v = float(std::acos(std::clamp(cos_theta, -1.0, 1.0)) / double(kPi));
  const float u_lon = (float(cell.x) + cell.within.x) / float(w);
  s.direction = equirect::uvToDirection({u_lon, v}, yaw_);
  s.radiance = rgbAt(panorama_, cell.x, cell.y);
  s.pdf = float(cell.probability / row_solid_angle_[cell.y]);
  return s;
}

vec3 Environment::radiance(const vec3& origin, const vec3& direction) const {
  return radiance(proxy_.lookupDirection(origin, direction));
}

float Environment::pdf(const vec3& origin, const vec3& direction) const {
  if (proxy_.infinite()) return pdf(direction);
  // p_origin(w) = p_centre(d) * dOmega_centre / dOmega_origin for the same patch of the sphere.
  return pdf(proxy_.lookupDirection(origin, direction)) * proxy_.solidAngleRatio(origin, direction);
}

EnvironmentSample Environment::sample(const vec2& u, const vec3& origin) const {
  EnvironmentSample s = sample(u);
  if (proxy_.infinite() || !(s.pdf > 0.0f)) return s;
  const vec3 m = origin - proxy_.centre;
  if (!(glm::dot(m, m) < proxy_.radius * proxy_.radius)) return s;  // outside the hall: no parallax
  const vec3 to_point = proxy_.centre + proxy_.radius * s.direction - origin;
  s.direction = glm::normalize(to_point);
  s.pdf *= proxy_.solidAngleRatio(origin, s.direction);
  return s;
}

}  // namespace holo::reflect
