// Synthetic foreground clouds for the tracer's tests and benchmarks: visitors standing around the
// pyramid, as the depth cameras see them (surface points of ellipsoids, about 1 cm apart).
#pragma once

#include <random>

#include "holo/depthfilter/foreground_cloud.hpp"

namespace holo::test {

// `visitors` standing `distance` metres from the pyramid axis, spread around it, each a body
// ellipsoid (0.22 x 0.8 x 0.15 m half-axes around 0.9 m height) plus a head sphere.
inline depthfilter::ForegroundCloud visitorCloud(int visitors, float distance, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  depthfilter::ForegroundCloud cloud;
  auto shell = [&](const vec3& centre, const vec3& radii, int count, std::uint16_t camera) {
    for (int i = 0; i < count; ++i) {
      const float z = 2.0f * u(rng) - 1.0f;
      const float phi = 2.0f * kPi * u(rng);
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const vec3 n(r * std::cos(phi), z, r * std::sin(phi));
      depthfilter::ForegroundPoint p;
      p.position = centre + n * radii;
      p.radiance = vec3(0.2f + 0.6f * u(rng), 0.3f, 0.2f + 0.5f * (n.y * 0.5f + 0.5f));
      p.weight = 0.5f + 0.5f * u(rng);
      p.camera = camera;
      p.x = std::uint16_t(u(rng) * 1279.0f);
      p.y = std::uint16_t(u(rng) * 719.0f);
      cloud.points.push_back(p);
    }
  };
  for (int v = 0; v < visitors; ++v) {
    const float a = 2.0f * kPi * (float(v) + 0.3f * u(rng)) / float(std::max(visitors, 1));
    const vec3 base(distance * std::cos(a), 0.0f, distance * std::sin(a));
    const auto camera = std::uint16_t(v % 4);
    shell(base + vec3(0.0f, 0.9f, 0.0f), vec3(0.22f, 0.8f, 0.15f), 40000, camera);
    shell(base + vec3(0.0f, 1.8f, 0.0f), vec3(0.1f, 0.12f, 0.1f), 4000, camera);
  }
  cloud.sequence = seed;
  return cloud;
}

}  // namespace holo::test
