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

// Distance along `direction` from `origin` (above it) to the base's top square; infinite when
// the ray misses it.
float baseDistance(const PanoramaProxy& proxy, const vec3& origin, const vec3& direction) {
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  if (!(proxy.base_half_width > 0.0f) || !(origin.y > 0.0f) || !(direction.y < 0.0f)) return kMiss;
  const float t = -origin.y / direction.y;
  const vec3 q = origin + t * direction;
  return std::abs(q.x) <= proxy.base_half_width && std::abs(q.z) <= proxy.base_half_width ? t : kMiss;
}

// Where the ray first meets the proxy (distance t > 0, and the proxy's unit normal there);
// false when it does not (an origin outside the sphere).
bool meetProxy(const PanoramaProxy& proxy, const vec3& origin, const vec3& direction, float& t,
               vec3& normal) {
  t = exitDistance(proxy, origin, direction);
  if (!(t > 0.0f)) return false;
  const float base = baseDistance(proxy, origin, direction);
  if (base < t) {
    t = base;
    normal = vec3(0.0f, 1.0f, 0.0f);
  } else {
    normal = (origin + t * direction - proxy.centre) / proxy.radius;
  }
  return true;
}

}  // namespace

vec3 PanoramaProxy::lookupDirection(const vec3& origin, const vec3& direction) const {
  if (infinite()) return direction;
  float t;
  vec3 normal;
  if (!meetProxy(*this, origin, direction, t, normal)) return direction;
  const vec3 to = origin + t * direction - centre;
  const float length = glm::length(to);
  return length > 1e-6f ? to / length : direction;
}

vec3 PanoramaProxy::point(const vec3& d) const {
  return centre + std::min(radius, baseDistance(*this, centre, d)) * d;
}

float PanoramaProxy::solidAngleRatio(const vec3& origin, const vec3& direction) const {
  if (infinite()) return 1.0f;
  float t;
  vec3 normal;
  if (!meetProxy(*this, origin, direction, t, normal)) return 1.0f;
  const vec3 to = origin + t * direction - centre;
  const float distance2 = std::max(glm::dot(to, to), 1e-12f);
  const float cos_centre = std::abs(glm::dot(normal, to)) / std::sqrt(distance2);
  const float cos_origin = std::max(std::abs(glm::dot(normal, direction)), 1e-6f);
  return t * t * cos_centre / (distance2 * cos_origin);
}

Environment::Environment(const cv::Mat& panorama, float yaw, PanoramaProxy proxy) : yaw_(yaw), proxy_(proxy) {
  if (panorama.empty() || panorama.type() != CV_32FC3)
    throw InputError("", "panorama", "a non-empty CV_32FC3 linear BGR image");
  if (!isFinite(proxy_.centre) || !(proxy_.radius > 0.0f))
    throw InputError("", "panorama proxy", "a finite centre and a radius > 0 metres (infinite: no parallax)");
  if (!std::isfinite(proxy_.base_half_width) || proxy_.base_half_width < 0.0f)
    throw InputError("", "panorama proxy", "a base half width >= 0 metres (0: no base)");
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
  for (const float f :
       {proxy_.centre.x, proxy_.centre.y, proxy_.centre.z, proxy_.radius, proxy_.base_half_width}) {
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
  const vec3 sampled = s.direction;
  s.direction = glm::normalize(proxy_.point(sampled) - origin);
  // A pixel the base hides from `origin` (it lies behind the base's edge seen from there, not
  // from the centre) is no light origin sees: no sample, so pdf() stays the density of those drawn.
  if (glm::dot(proxy_.lookupDirection(origin, s.direction), sampled) < 1.0f - 1e-5f)
    return EnvironmentSample{};
  s.pdf *= proxy_.solidAngleRatio(origin, s.direction);
  return s;
}

}  // namespace holo::reflect
