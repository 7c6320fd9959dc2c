#include "holo/reflect/panorama_sun.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "holo/core/equirect.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "holo/reflect/lobe_integral.hpp"

namespace holo::reflect {
namespace {

// Integral over the sphere of ggxLobeWeight(n.l, k1): 2 pi int_0^1 c / (1 - (1 + c) k1)^2 dc, in
// closed form 2 pi / k1^2 (k1 / alpha^2 + ln(alpha^2 / (1 - k1))) with alpha^2 = 1 - 2 k1; its
// series 2 pi (1 / 2 + 5 k1 / 3) where k1 is too small for the closed form's difference.
double lobeWeightIntegral(double k1) {
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  if (k1 < 1e-2) return kTwoPi * (0.5 + 5.0 * k1 / 3.0);
  const double a2 = std::max(1.0 - 2.0 * k1, 1e-12);
  return kTwoPi / (k1 * k1) * (k1 / a2 + std::log(a2 / (1.0 - k1)));
}

}  // namespace

std::string PanoramaSun::describe() const {
  char text[160];
  if (!found) {
    std::snprintf(text, sizeof text, "no sun (brightest pixel %.0fx the mean, %.0f%% of the light in %d px)",
                  double(peak_ratio), double(share) * 100.0, pixels);
    return text;
  }
  const float elevation = std::asin(std::clamp(direction.y, -1.0f, 1.0f)) * 180.0f / kPi;
  std::snprintf(text, sizeof text, "sun at %.0f deg elevation, %.1e sr, %.0f%% of the light",
                double(elevation), double(solid_angle), double(share) * 100.0);
  return text;
}

vec3 PanoramaSun::lobe(const vec3& at, float roughness) const {
  if (!found) return vec3(0.0f);
  const float alpha = std::max(roughnessToAlpha(std::clamp(roughness, 1e-3f, 1.0f)), 1e-3f);
  const float k1 = ggxLobeK1(alpha);
  return power * float(double(ggxLobeWeight(glm::dot(at, direction), k1)) / lobeWeightIntegral(double(k1)));
}

PanoramaSun findPanoramaSun(const Environment& environment, const SunSearchSettings& settings) {
  PanoramaSun sun;
  const cv::Mat& pano = environment.panorama();
  if (pano.empty()) return sun;
  const int w = pano.cols, h = pano.rows;
  std::vector<float> lum(std::size_t(w) * std::size_t(h));
  double total = 0.0;
  int peak = 0;
  for (int y = 0; y < h; ++y) {
    const double omega = Environment::pixelSolidAngle(y, w, h);
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
      lum[i] = luminance(rgbAt(pano, x, y));
      total += double(lum[i]) * omega;
      if (lum[i] > lum[std::size_t(peak)]) peak = int(i);
    }
  }
  if (!(total > 0.0)) return sun;
  const double mean = total / (4.0 * double(kPi));
  sun.peak_ratio = float(double(lum[std::size_t(peak)]) / mean);
  const float threshold = float(mean) * settings.threshold_ratio;
  if (!(lum[std::size_t(peak)] > threshold)) return sun;

  // The region: flood fill from the brightest pixel (8-connected, wrapping in x).
  std::vector<std::uint8_t> state(lum.size(), 0);  // 1: in the region, 2: bordering it
  std::vector<int> stack{peak}, region, border;
  state[std::size_t(peak)] = 1;
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    region.push_back(i);
    const int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int ny = y + dy;
        if ((dx == 0 && dy == 0) || ny < 0 || ny >= h) continue;
        const int j = ny * w + (x + dx + w) % w;
        if (state[std::size_t(j)] != 0) continue;
        state[std::size_t(j)] = lum[std::size_t(j)] > threshold ? 1 : 2;
        (state[std::size_t(j)] == 1 ? stack : border).push_back(j);
      }
  }
  vec3 sky(0.0f);
  for (int j : border) sky += rgbAt(pano, j % w, j / w);
  if (!border.empty()) sky /= float(border.size());

  glm::dvec3 power(0.0), centroid(0.0);
  std::array<glm::dvec3, 9> sh{};
  double omega_sum = 0.0, excess_lum = 0.0;
  for (int i : region) {
    const int x = i % w, y = i / w;
    const double omega = Environment::pixelSolidAngle(y, w, h);
    const vec3 excess = glm::max(rgbAt(pano, x, y) - sky, vec3(0.0f));
    const vec3 d = equirect::uvToDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)},
                                           environment.yaw());
    const glm::dvec3 e = glm::dvec3(excess) * omega;
    power += e;
    excess_lum += double(luminance(excess)) * omega;
    centroid += glm::dvec3(d) * (double(luminance(excess)) * omega);
    const auto b = IrradianceSH::basis(d);
    for (int k = 0; k < 9; ++k) sh[std::size_t(k)] += e * double(b[std::size_t(k)]);
    omega_sum += omega;
  }
  sun.pixels = int(region.size());
  sun.solid_angle = float(omega_sum);
  sun.share = float(excess_lum / total);
  if (!(sun.solid_angle <= settings.max_solid_angle) || !(sun.share >= settings.min_share) ||
      !(glm::length(centroid) > 0.0))
    return sun;
  sun.found = true;
  sun.direction = vec3(glm::normalize(centroid));
  sun.power = vec3(power);
  for (int k = 0; k < 9; ++k) sun.radiance_sh[std::size_t(k)] = vec3(sh[std::size_t(k)]);
  return sun;
}

}  // namespace holo::reflect
