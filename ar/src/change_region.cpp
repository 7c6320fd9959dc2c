#include "holo/ar/change_region.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::ar {
namespace {

float angleBetween(const vec3& a, const vec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f));
}

float maxChannel(const vec3& v) {
  return std::max(v.x, std::max(v.y, v.z));
}

// The cone from the cell's centre direction holding its corners and edge midpoints (an
// equirectangular cell's farthest directions from its centre lie on its border).
PanoramaLightBound::Cone cellCone(int x0, int x1, int y0, int y1, int width, int height, float yaw) {
  const auto direction = [&](float x, float y) {
    return equirect::uvToDirection({x / static_cast<float>(width), y / static_cast<float>(height)}, yaw);
  };
  const float cx = 0.5f * static_cast<float>(x0 + x1), cy = 0.5f * static_cast<float>(y0 + y1);
  PanoramaLightBound::Cone cone;
  cone.direction = direction(cx, cy);
  const float xs[3] = {static_cast<float>(x0), cx, static_cast<float>(x1)};
  const float ys[3] = {static_cast<float>(y0), cy, static_cast<float>(y1)};
  for (const float x : xs)
    for (const float y : ys)
      cone.half_angle = std::max(cone.half_angle, angleBetween(cone.direction, direction(x, y)));
  // A cell's border between its sample points bulges by less than its own span's sagitta.
  cone.half_angle *= 1.05f;
  cone.half_angle += 1e-3f;
  return cone;
}

// The sRGB code change (8-bit) of a background b moved by up to +-delta at the exposure.
float codeChange(float b, float delta, float exposure) {
  const float code = linearToSrgb(exposure * b);
  const float up = linearToSrgb(exposure * (b + delta)) - code;
  const float down = code - linearToSrgb(exposure * std::max(0.0f, b - delta));
  return 255.0f * std::max(up, down);
}

}  // namespace

PanoramaLightBound panoramaLightBound(const reflect::Environment& environment) {
  PanoramaLightBound out;
  const cv::Mat& pano = environment.panorama();
  if (pano.empty()) return out;
  const int w = pano.cols, h = pano.rows;
  const int cells_x = std::min(w, PanoramaLightBound::kCells),
            cells_y = std::min(h, PanoramaLightBound::kCells / 2);
  struct Cell {
    vec3 max{0.0f};
    vec3 integral{0.0f};
  };
  std::vector<Cell> cells(static_cast<std::size_t>(cells_x) * static_cast<std::size_t>(cells_y));
  vec3 total(0.0f);
  for (int y = 0; y < h; ++y) {
    const float solid_angle = static_cast<float>(reflect::Environment::pixelSolidAngle(y, w, h));
    const int cy = y * cells_y / h;
    for (int x = 0; x < w; ++x) {
      Cell& cell = cells[static_cast<std::size_t>(cy) * static_cast<std::size_t>(cells_x) +
                         static_cast<std::size_t>(x * cells_x / w)];
      const vec3 radiance = rgbAt(pano, x, y);
      cell.max = glm::max(cell.max, radiance);
      out.max_radiance = glm::max(out.max_radiance, radiance);
      cell.integral += radiance * solid_angle;
      total += radiance * solid_angle;
    }
  }
  const float bright_above =
      PanoramaLightBound::kBrightOverMean * maxChannel(total) / (4.0f * glm::pi<float>());
  for (int cy = 0; cy < cells_y; ++cy)
    for (int cx = 0; cx < cells_x; ++cx) {
      const Cell& cell = cells[static_cast<std::size_t>(cy) * static_cast<std::size_t>(cells_x) +
                               static_cast<std::size_t>(cx)];
      if (maxChannel(cell.max) > bright_above) {
        // The cell's pixel range: every pixel x with x * cells_x / w == cx.
        const int x0 = (cx * w + cells_x - 1) / cells_x, x1 = ((cx + 1) * w + cells_x - 1) / cells_x;
        const int y0 = (cy * h + cells_y - 1) / cells_y, y1 = ((cy + 1) * h + cells_y - 1) / cells_y;
        out.bright.push_back(cellCone(x0, x1, y0, y1, w, h, environment.yaw()));
        out.bright_irradiance += cell.integral;
      } else {
        out.dim_radiance = glm::max(out.dim_radiance, cell.max);
      }
    }
  return out;
}

cv::Mat changeRegion(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                     const ChangeRegionSettings& s) {
  const int w = camera.width(), h = camera.height();
  if (background.type() != CV_32FC3 || background.cols != w || background.rows != h)
    throw InputError("AR change region", "background", "CV_32FC3 radiance of the camera's size");
  if (!(s.negligible_codes > 0.0f))
    throw InputError("AR change region", "negligible_codes", "a bound > 0 codes");
  const RelicBounds& relic = scene.relicBounds();
  if (relic.empty()) return cv::Mat(h, w, CV_8UC1, cv::Scalar(0));
  const vec3 eye = camera.ray({0.0f, 0.0f}).origin;
  if (!scene.environment().proxy().infinite() || glm::length(relic.centre - eye) <= relic.radius)
    return cv::Mat(h, w, CV_8UC1, cv::Scalar(255));
  const PanoramaLightBound light = panoramaLightBound(scene.environment());
  const vec3 relic_radiance = scene.relicTransmits()
                                  ? light.max_radiance
                                  : light.dim_radiance + light.bright_irradiance / glm::pi<float>();
  const float exposure = s.exposure > 0.0f ? s.exposure : 1.0f;
  // The bright cones with their half angles' cosine and sine (a half angle capped at a quarter turn,
  // whose test already holds every direction towards the sphere's side of the sky).
  struct BrightCone {
    vec3 direction;
    float cos_half, sin_half;
  };
  std::vector<BrightCone> bright;
  for (const PanoramaLightBound::Cone& cone : light.bright) {
    const float half = std::min(cone.half_angle, 0.5f * glm::pi<float>());
    bright.push_back({cone.direction, std::cos(half), std::sin(half)});
  }

  // Whether a real surface point may see a displayed change (the header's bound).
  const auto changes = [&](const vec3& p, const vec3& n, const vec3& albedo, const vec3& seen) {
    const vec3 to_relic = relic.centre - p;
    const float distance = glm::length(to_relic);
    if (distance <= relic.radius) return true;
    const vec3 towards = to_relic / distance;
    // The sphere's angular radius alpha at p, as its sine and cosine.
    const float sin_alpha = relic.radius / distance;
    const float cos_alpha = std::sqrt(std::max(0.0f, 1.0f - sin_alpha * sin_alpha));
    const float cos_elevation = glm::dot(n, towards);
    if (cos_elevation <= -sin_alpha) return false;  // wholly below the horizon
    for (const BrightCone& cone : bright)
      if (glm::dot(cone.direction, n) > -cone.sin_half &&
          glm::dot(cone.direction, towards) >= cone.cos_half * cos_alpha - cone.sin_half * sin_alpha)
        return true;
    const float solid_angle = 2.0f * glm::pi<float>() * (1.0f - cos_alpha);
    // The largest cosine to the normal over the sphere's cone: cos(max(0, elevation - alpha)).
    const float sin_elevation = std::sqrt(std::max(0.0f, 1.0f - cos_elevation * cos_elevation));
    const float cos_max =
        cos_elevation >= cos_alpha ? 1.0f : cos_elevation * cos_alpha + sin_elevation * sin_alpha;
    const vec3 delta = albedo * (solid_angle * cos_max / glm::pi<float>()) * relic_radiance;
    return codeChange(seen.x, delta.x, exposure) >= s.negligible_codes ||
           codeChange(seen.y, delta.y, exposure) >= s.negligible_codes ||
           codeChange(seen.z, delta.z, exposure) >= s.negligible_codes;
  };

  // A pixel's samples lie within its corners' rays: the widest angle from a pixel's centre ray to
  // a corner's over a 5 x 5 grid of pixels across the image, doubled for the pixels between.
  float footprint = 0.0f;
  for (int gy = 0; gy <= 4; ++gy)
    for (int gx = 0; gx <= 4; ++gx) {
      const vec2 centre(static_cast<float>(gx * (w - 1)) / 4.0f, static_cast<float>(gy * (h - 1)) / 4.0f);
      const vec3 direction = camera.ray(centre).direction;
      for (const vec2 corner : {vec2(-0.5f, -0.5f), vec2(0.5f, -0.5f), vec2(-0.5f, 0.5f), vec2(0.5f, 0.5f)})
        footprint = std::max(footprint, angleBetween(direction, camera.ray(centre + corner).direction));
    }
  footprint *= 2.0f;
  const float cos_footprint = std::cos(footprint), sin_footprint = std::sin(footprint);
  const vec3 to_relic_from_eye = relic.centre - eye;
  const float eye_distance = glm::length(to_relic_from_eye);
  const float sin_relic = relic.radius / eye_distance;
  const float cos_relic = std::sqrt(std::max(0.0f, 1.0f - sin_relic * sin_relic));
  // cos(the relic's angular radius + the footprint), or -1 past a half turn.
  const float cos_reach = std::asin(sin_relic) + footprint >= glm::pi<float>()
                              ? -1.0f
                              : cos_relic * cos_footprint - sin_relic * sin_footprint;
  const vec3 towards_relic = to_relic_from_eye / eye_distance;

  cv::Mat region(h, w, CV_8UC1, cv::Scalar(0));
  tbb::parallel_for(0, h, [&](int y) {
    std::uint8_t* row = region.ptr<std::uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      const Ray ray = camera.ray({static_cast<float>(x), static_cast<float>(y)});
      if (glm::dot(ray.direction, towards_relic) >= cos_reach) {
        row[x] = 255;
        continue;
      }
      const RayHit hit = scene.intersect(SceneContent::kReal, ray);
      if (!hit.hit()) continue;
      const vec3 p = ray.origin + hit.t * ray.direction;
      const vec3 n = scene.shadingNormal(hit, ray.direction);
      if (changes(p, n, scene.realAlbedo(hit), rgbAt(background, x, y))) row[x] = 255;
    }
  });
  cv::dilate(region, region, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  return region;
}

}  // namespace holo::ar
