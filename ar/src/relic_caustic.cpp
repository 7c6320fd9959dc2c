#include "holo/ar/relic_caustic.hpp"

#include <cmath>

#include "holo/core/image.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/transmissive_relic.hpp"

namespace holo::ar {
bool RelicCaustic::onReceiver(const vec3& p, const vec3& n) const {
  return std::abs(p.y - image_.grid.height) <= tolerance_ && n.y >= min_cos_;
}

vec3 RelicCaustic::irradianceAt(const vec3& p) const {
  const reflect::CausticReceiverGrid& g = image_.grid;
  // Cell centres at integer coordinates.
  const vec2 q = (vec2(p.x, p.z) - g.centre + g.half_size) / g.cellSize() - 0.5f;
  const int x0 = static_cast<int>(std::floor(q.x)), z0 = static_cast<int>(std::floor(q.y));
  const float fx = q.x - static_cast<float>(x0), fz = q.y - static_cast<float>(z0);
  const auto at = [&](int x, int z) {
    if (x < 0 || z < 0 || x >= g.resolution || z >= g.resolution) return vec3(0.0f);
    return rgbAt(image_.irradiance, x, z);
  };
  return (1.0f - fz) * ((1.0f - fx) * at(x0, z0) + fx * at(x0 + 1, z0)) +
         fz * ((1.0f - fx) * at(x0, z0 + 1) + fx * at(x0 + 1, z0 + 1));
}

void addCausticToRegion(const RelicCaustic& caustic, const CameraModel& camera, const cv::Mat& background,
                        float negligible_codes, float exposure, cv::Mat& region) {
  if (region.empty()) return;
  const reflect::CausticReceiverGrid& g = caustic.image().grid;
  const float cell = g.cellSize();
  const cv::Rect image(0, 0, region.cols, region.rows);
  for (int z = 0; z < g.resolution; ++z)
    for (int x = 0; x < g.resolution; ++x) {
      const vec3 e = rgbAt(caustic.image().irradiance, x, z);
      if (!(maxComponent(e) > 0.0f)) continue;
      const vec2 corner = g.centre - g.half_size + cell * vec2(static_cast<float>(x), static_cast<float>(z));
      cv::Rect covered;
      bool seen = true;
      for (int k = 0; k < 4 && seen; ++k) {
        const vec3 p(corner.x + cell * static_cast<float>(k & 1), g.height,
                     corner.y + cell * static_cast<float>(k >> 1));
        const std::optional<vec2> pixel = camera.project(p);
        seen = pixel.has_value();
        if (!seen) break;
        const cv::Rect at(static_cast<int>(std::floor(pixel->x)) - 1,
                          static_cast<int>(std::floor(pixel->y)) - 1, 3, 3);
        covered = k == 0 ? at : (covered | at);
      }
      covered &= image;
      if (!seen || covered.empty()) continue;
      const cv::Point centre(covered.x + covered.width / 2, covered.y + covered.height / 2);
      const vec3 b = exposure * rgbAt(background, centre.x, centre.y);
      const vec3 added = exposure * e * (1.0f / kPi);
      bool visible = false;
      for (int c = 0; c < 3; ++c)
        visible =
            visible || 255.0f * (linearToSrgb(b[c] + added[c]) - linearToSrgb(b[c])) >= negligible_codes;
      if (visible) region(covered).setTo(255);
    }
}

std::optional<RelicCaustic> traceRelicCaustic(const Model& relic, const reflect::Environment& environment,
                                              const RelicCausticSettings& settings) {
  if (!settings.enabled || !reflect::modelTransmits(relic)) return std::nullopt;
  const Bounds3 bounds = relic.bounds();
  if (bounds.empty() || bounds.lo.y < settings.receiver_height - RelicCausticSettings::kStandingTolerance)
    return std::nullopt;
  const reflect::RenderScene scene(relic, {});
  const float radius = 0.5f * glm::length(bounds.extent());
  reflect::CausticReceiverGrid grid;
  grid.centre = vec2(bounds.center().x, bounds.center().z);
  grid.half_size = settings.half_size_radii * radius;
  grid.height = settings.receiver_height;
  grid.resolution = settings.resolution;
  reflect::CausticTracerSettings trace;
  trace.photons = settings.photons;
  trace.seed = settings.seed;
  return RelicCaustic(reflect::traceEnvironmentCaustics(scene, environment, grid, trace),
                      settings.receiver_tolerance, settings.receiver_min_cos);
}

}  // namespace holo::ar
