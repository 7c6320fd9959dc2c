#include "holo/reflect/irradiance_sh.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cmath>

#include "holo/core/equirect.hpp"

namespace holo::reflect {

std::array<float, 9> IrradianceSH::basis(const vec3& d) {
  return {0.282095f,
          0.488603f * d.y,
          0.488603f * d.z,
          0.488603f * d.x,
          1.092548f * d.x * d.y,
          1.092548f * d.y * d.z,
          0.315392f * (3.0f * d.z * d.z - 1.0f),
          1.092548f * d.x * d.z,
          0.546274f * (d.x * d.x - d.y * d.y)};
}

namespace {

using Coefficients = std::array<glm::dvec3, 9>;

}  // namespace

IrradianceSH::IrradianceSH(const Environment& environment) {
  const cv::Mat& pano = environment.panorama();
  if (pano.empty()) return;
  const int w = pano.cols, h = pano.rows;
  // Deterministic reduce: the partial sums are joined in the same order whatever the threads
  // did, so the coefficients (and every image lit by them) are bit-identical run to run.
  const Coefficients sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, h, 16), Coefficients{},
      [&](const tbb::blocked_range<int>& rows, Coefficients acc) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          const double omega = Environment::pixelSolidAngle(y, w, h);
          for (int x = 0; x < w; ++x) {
            const vec3 d = equirect::uvToDirection(
                {(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}, environment.yaw());
            const glm::dvec3 L = glm::dvec3(rgbAt(pano, x, y)) * omega;
            const auto b = basis(d);
            for (int i = 0; i < 9; ++i) acc[i] += L * double(b[i]);
          }
        }
        return acc;
      },
      [](Coefficients a, const Coefficients& b) {
        for (int i = 0; i < 9; ++i) a[i] += b[i];
        return a;
      });
  for (int i = 0; i < 9; ++i) c_[i] = vec3(sum[i]);
}

vec3 IrradianceSH::irradiance(const vec3& n) const {
  const auto b = basis(n);
  vec3 e(0.0f);
  for (int i = 0; i < 9; ++i) e += kCosineLobe[i] * c_[i] * b[i];
  return glm::max(e, vec3(0.0f));
}

std::array<vec3, 9> IrradianceSH::turnedAboutY(float cos_a, float sin_a) const {
  // L'_j = sum_k L_k integral Y_j(d) Y_k(turn(d)) dd. The integrands are polynomials of degree
  // <= 4, so a product rule is exact: 3 Gauss-Legendre nodes in y (exact to degree 5) times 8
  // equally spaced azimuths (exact to trigonometric degree 7).
  constexpr float kNodes[3] = {-0.7745966692f, 0.0f, 0.7745966692f};
  constexpr float kWeights[3] = {5.0f / 9.0f, 8.0f / 9.0f, 5.0f / 9.0f};
  constexpr int kAzimuths = 8;
  std::array<vec3, 9> turned{};
  for (int i = 0; i < 3; ++i) {
    const float y = kNodes[i], r = std::sqrt(1.0f - y * y);
    for (int k = 0; k < kAzimuths; ++k) {
      const float phi = 2.0f * kPi * float(k) / float(kAzimuths);
      const vec3 d(r * std::cos(phi), y, r * std::sin(phi));
      const vec3 t(cos_a * d.x + sin_a * d.z, d.y, cos_a * d.z - sin_a * d.x);
      const float w = kWeights[i] * 2.0f * kPi / float(kAzimuths);
      const auto bd = basis(d), bt = basis(t);
      vec3 radiance(0.0f);  // L(turn(d)) of the 9-coefficient approximation
      for (int c = 0; c < 9; ++c) radiance += c_[c] * bt[c];
      for (int j = 0; j < 9; ++j) turned[j] += w * bd[j] * radiance;
    }
  }
  return turned;
}

}  // namespace holo::reflect
