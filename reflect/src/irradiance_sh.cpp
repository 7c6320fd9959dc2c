#include "holo/reflect/irradiance_sh.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "holo/core/equirect.hpp"

namespace holo::reflect {

namespace {

std::array<float, 9> basis(const vec3& d) {
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
  // Cosine-lobe convolution factors A_l: pi, 2 pi / 3, pi / 4.
  constexpr float a0 = kPi, a1 = 2.0f * kPi / 3.0f, a2 = kPi / 4.0f;
  const auto b = basis(n);
  vec3 e = a0 * c_[0] * b[0];
  for (int i = 1; i < 4; ++i) e += a1 * c_[i] * b[i];
  for (int i = 4; i < 9; ++i) e += a2 * c_[i] * b[i];
  return glm::max(e, vec3(0.0f));
}

}  // namespace holo::reflect
