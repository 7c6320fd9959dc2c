#include "plinth_light.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "environment_directions.hpp"
#include "holo/reflect/view.hpp"

namespace holo::reflect {

namespace {

// Bilinear read of a BGR CV_32FC3 grid over a square of `half` round `centre`, as RGB; 0 outside.
vec3 readGrid(const cv::Mat& grid, const vec2& centre, float half, const vec2& xz) {
  if (grid.empty()) return vec3(0.0f);
  const int res = grid.cols;
  const vec2 q = (xz - centre + half) / (2.0f * half) * float(res) - 0.5f;
  const int x0 = int(std::floor(q.x)), z0 = int(std::floor(q.y));
  const float fx = q.x - float(x0), fz = q.y - float(z0);
  vec3 sum(0.0f);
  for (int dz = 0; dz <= 1; ++dz)
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = std::clamp(x0 + dx, 0, res - 1), z = std::clamp(z0 + dz, 0, res - 1);
      const float w = (dx ? fx : 1.0f - fx) * (dz ? fz : 1.0f - fz);
      const cv::Vec3f v = grid.at<cv::Vec3f>(z, x);
      sum += w * vec3(v[2], v[1], v[0]);
    }
  return sum;
}

}  // namespace

PlinthLight::PlinthLight(const PlinthBox& box, int resolution, int shadow_rays)
    : box_(box), resolution_(std::max(1, resolution)), shadow_rays_(std::max(1, shadow_rays)) {}

std::uint64_t PlinthLight::light(const RenderScene& scene, const PrefilteredIbl& ibl,
                                 const CausticImage* caustic, bool shadow) {
  unshadowed_top_ = ibl.irradiance(vec3(0.0f, 1.0f, 0.0f));
  caustic_ = caustic ? *caustic : CausticImage{};
  const int res = resolution_;
  blocked_.assign(std::size_t(res) * std::size_t(res), vec3(0.0f));
  if (!shadow) return 0;
  // Half the rays cosine-distributed over strata, half drawn from the hall's bright directions
  // (its small lamps), combined by the balance heuristic.
  const int strata = std::max(1, int(std::lround(std::sqrt(0.5 * double(shadow_rays_)))));
  const int cosine_rays = strata * strata, hall_rays = strata * strata;
  const float c = std::cos(ibl.relicTurn()), s = std::sin(ibl.relicTurn());
  const auto toHall = [c, s](const vec3& d) { return vec3(c * d.x + s * d.z, d.y, c * d.z - s * d.x); };
  const OctahedralMap& sharp = ibl.level(0);
  const EnvironmentDirections directions(sharp);
  const RayScene& relic = scene.relicOnly();
  const float texel = 2.0f * box_.half_width / float(res);
  const float lift = 1e-4f * std::max(1e-3f, box_.half_width);
  tbb::parallel_for(0, res, [&](int z) {
    std::vector<Ray> rays(std::size_t(cosine_rays + hall_rays));
    std::vector<RayHit> found(rays.size());
    for (int x = 0; x < res; ++x) {
      const vec3 origin(box_.centre.x - box_.half_width + (float(x) + 0.5f) * texel, box_.top + lift,
                        box_.centre.y - box_.half_width + (float(z) + 0.5f) * texel);
      // The strata's offsets hashed from the texel so neighbouring texels do not share a pattern.
      std::uint32_t h = std::uint32_t(z * 73856093) ^ std::uint32_t(x * 19349663);
      const auto next = [&h] {
        h = h * 1664525u + 1013904223u;
        return float(h >> 8) / 16777216.0f;
      };
      for (int j = 0; j < strata; ++j)
        for (int i = 0; i < strata; ++i) {
          const float u1 = (float(i) + next()) / float(strata), u2 = (float(j) + next()) / float(strata);
          const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
          rays[std::size_t(j * strata + i)] =
              Ray{origin, vec3(r * std::cos(phi), std::sqrt(std::max(0.0f, 1.0f - u1)), r * std::sin(phi))};
        }
      for (int k = 0; k < hall_rays; ++k) {
        const float u1 = next(), u2 = next();
        const vec3 hall =
            directions.empty() ? vec3(0.0f, -1.0f, 0.0f) : directions.sample(vec2(u1, u2)).direction;
        // The hall direction in the relic's frame: toHall inverted.
        rays[std::size_t(cosine_rays + k)] =
            Ray{origin, vec3(c * hall.x - s * hall.z, hall.y, s * hall.x + c * hall.z)};
      }
      relic.intersectCoherent(rays, found, 0.0f, 1e30f);
      vec3 sum(0.0f);
      for (std::size_t k = 0; k < rays.size(); ++k) {
        const vec3& d = rays[k].direction;
        if (!found[k].hit() || d.y <= 0.0f) continue;
        const vec3 hall = toHall(d);
        const double p = double(cosine_rays) * double(d.y) / double(kPi) +
                         (directions.empty() ? 0.0 : double(hall_rays) * directions.pdf(hall));
        if (p > 0.0) sum += sharp.bilinear(hall) * float(double(d.y) / p);
      }
      blocked_[std::size_t(z) * std::size_t(res) + std::size_t(x)] = sum;
    }
  });
  return std::uint64_t(res) * std::uint64_t(res) * std::uint64_t(cosine_rays + hall_rays);
}

vec3 PlinthLight::irradiance(const vec3& position, const vec3& normal, const PrefilteredIbl& ibl) const {
  if (normal.y < 0.5f) return ibl.irradiance(normal);
  const vec2 xz(position.x, position.z);
  const int res = resolution_;
  // Bilinear over the texel centres, clamped at the edges.
  const vec2 q = (xz - box_.centre + box_.half_width) / (2.0f * box_.half_width) * float(res) - 0.5f;
  const int x0 = int(std::floor(q.x)), z0 = int(std::floor(q.y));
  const float fx = q.x - float(x0), fz = q.y - float(z0);
  vec3 blocked(0.0f);
  for (int dz = 0; dz <= 1; ++dz)
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = std::clamp(x0 + dx, 0, res - 1), z = std::clamp(z0 + dz, 0, res - 1);
      blocked += (dx ? fx : 1.0f - fx) * (dz ? fz : 1.0f - fz) *
                 blocked_[std::size_t(z) * std::size_t(res) + std::size_t(x)];
    }
  vec3 e = unshadowed_top_ - blocked;
  if (!caustic_.irradiance.empty())
    e += readGrid(caustic_.irradiance, caustic_.grid.centre, caustic_.grid.half_size, xz);
  return glm::max(e, vec3(0.0f));
}

void drawPlinth(const PlinthLight& light, const PrefilteredIbl& ibl, const CameraModel& view,
                const HitPointBuffer& hits, cv::Mat& hdr, std::vector<std::uint32_t>& pixels) {
  const PlinthBox& box = light.box();
  const int w = view.width(), h = view.height();
  // The box's projected rectangle (all of the view when a corner is behind the eye).
  int x_lo = 0, x_hi = w - 1, y_lo = 0, y_hi = h - 1;
  {
    const Bounds3 b = box.bounds();
    float px_lo = 1e30f, px_hi = -1e30f, py_lo = 1e30f, py_hi = -1e30f;
    bool all_in_front = true;
    for (int k = 0; k < 8; ++k) {
      const vec3 p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
      float depth = 0.0f;
      const auto q = view.project(p, &depth);
      if (!q || depth <= 0.0f) {
        all_in_front = false;
        break;
      }
      px_lo = std::min(px_lo, q->x), px_hi = std::max(px_hi, q->x);
      py_lo = std::min(py_lo, q->y), py_hi = std::max(py_hi, q->y);
    }
    if (all_in_front && !view.intrinsics().hasDistortion()) {
      x_lo = std::max(0, int(std::floor(px_lo)) - 1), x_hi = std::min(w - 1, int(std::ceil(px_hi)) + 1);
      y_lo = std::max(0, int(std::floor(py_lo)) - 1), y_hi = std::min(h - 1, int(std::ceil(py_hi)) + 1);
    }
  }
  if (x_lo > x_hi || y_lo > y_hi) return;
  const std::vector<vec2> pattern = subsamplePattern(4);
  const vec3 albedo_over_pi = box.albedo / kPi;
  const vec3 eye = view.position();
  std::vector<std::vector<std::uint32_t>> rows(std::size_t(y_hi - y_lo + 1));
  tbb::parallel_for(y_lo, y_hi + 1, [&](int y) {
    auto* row = hdr.ptr<cv::Vec3f>(y);
    for (int x = x_lo; x <= x_hi; ++x) {
      vec3 sum(0.0f);
      int seen = 0;
      float nearest = 1e30f;
      for (const vec2& o : pattern) {
        const Ray ray = primaryRay(view, vec2(float(x), float(y)) + o);
        const auto hit = intersectPlinth(box, ray);
        if (!hit) continue;
        ++seen;
        nearest = std::min(nearest, hit->t);
        sum += albedo_over_pi * light.irradiance(ray.origin + hit->t * ray.direction, hit->normal, ibl);
      }
      if (seen == 0) continue;
      const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
      const vec3 plinth = sum / float(pattern.size());
      const float coverage = hits.coverage(x, y);
      const bool relic_nearer =
          coverage > 0.0f && (!hits.valid[p] || glm::distance(eye, hits.hits[p].position) < nearest);
      cv::Vec3f& px = row[x];
      const vec3 relic(px[2], px[1], px[0]);
      const vec3 out = relic_nearer ? relic + (1.0f - coverage) * plinth
                                    : plinth + (1.0f - float(seen) / float(pattern.size())) * relic;
      px = cv::Vec3f(out.z, out.y, out.x);
      rows[std::size_t(y - y_lo)].push_back(std::uint32_t(p));
    }
  });
  for (const auto& r : rows) pixels.insert(pixels.end(), r.begin(), r.end());
}

}  // namespace holo::reflect
