// The hall's directions as a distribution (internal): the prefiltered IBL's sharpest level, each
// octahedral texel weighted by its luminance times its solid angle, so its lamps and windows are
// drawn first. Shared by the caustic's photons (caustic_tracer.cpp) and the plinth's shadow
// (plinth_light.cpp). Directions in the hall's frame; pdf per steradian.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "holo/reflect/distribution.hpp"
#include "holo/reflect/octahedral_map.hpp"

namespace holo::reflect {

class EnvironmentDirections {
 public:
  explicit EnvironmentDirections(const OctahedralMap& map) : map_(map), size_(map.size()) {
    std::vector<double> weights(std::size_t(size_) * std::size_t(size_));
    solid_.resize(weights.size());
    double total = 0.0;
    for (int y = 0; y < size_; ++y)
      for (int x = 0; x < size_; ++x) {
        const auto corner = [&](int dx, int dy) {
          return octahedralDecode(vec2(float(x + dx), float(y + dy)) / float(size_));
        };
        const vec3 a = corner(0, 0), b = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
        const double omega = 0.5 * (double(glm::length(glm::cross(b - a, c - a))) +
                                    double(glm::length(glm::cross(c - a, d - a))));
        solid_[index(x, y)] = omega;
        total += omega;
      }
    for (std::size_t i = 0; i < solid_.size(); ++i) {
      solid_[i] *= 4.0 * double(kPi) / total;  // the flat-triangle areas, made to sum to 4 pi
      const vec3 L = map.at(int(i % std::size_t(size_)), int(i / std::size_t(size_)));
      weights[i] = double(luminance(L)) * solid_[i];
    }
    distribution_ = Distribution2D(weights, size_, size_);
  }

  bool empty() const { return distribution_.empty(); }

  struct Sample {
    vec3 direction{0.0f, 1.0f, 0.0f};  // hall frame, unit
    vec3 radiance{0.0f};               // the texel's
    double pdf = 0.0;                  // per steradian; 0: nothing drawn
  };
  Sample sample(const vec2& u) const {
    const Distribution2D::Sample pick = distribution_.sample(u);
    Sample s;
    if (!(pick.probability > 0.0)) return s;
    s.direction =
        glm::normalize(octahedralDecode((vec2(float(pick.x), float(pick.y)) + pick.within) / float(size_)));
    s.radiance = map_.at(pick.x, pick.y);
    s.pdf = pick.probability / solid_[index(pick.x, pick.y)];
    return s;
  }
  double pdf(const vec3& hall_direction) const {
    const vec2 uv = octahedralEncode(hall_direction) * float(size_);
    const int x = std::min(size_ - 1, std::max(0, int(uv.x))),
              y = std::min(size_ - 1, std::max(0, int(uv.y)));
    return distribution_.probability(x, y) / solid_[index(x, y)];
  }

 private:
  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(size_) + std::size_t(x); }
  const OctahedralMap& map_;
  int size_;
  std::vector<double> solid_;
  Distribution2D distribution_;
};

}  // namespace holo::reflect
