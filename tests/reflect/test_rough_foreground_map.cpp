#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/reflect/rough_foreground_map.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

// Points every ~1 cm on the part of a sphere of `radius` around `centre` within `cone` radians of
// `axis` (the whole sphere for cone >= pi).
ForegroundCloud sphereCap(const vec3& centre, float radius, const vec3& axis, float cone,
                          const vec3& radiance) {
  ForegroundCloud cloud;
  const int rows = int(kPi * radius / 0.01f);
  for (int i = 0; i < rows; ++i) {
    const float theta = kPi * (float(i) + 0.5f) / float(rows);
    const int cols = std::max(1, int(2.0f * kPi * radius * std::sin(theta) / 0.01f));
    for (int j = 0; j < cols; ++j) {
      const float phi = 2.0f * kPi * float(j) / float(cols);
      const vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      if (std::acos(std::clamp(glm::dot(d, axis), -1.0f, 1.0f)) > cone) continue;
      ForegroundPoint p;
      p.position = centre + radius * d;
      p.radiance = radiance;
      cloud.points.push_back(p);
    }
  }
  return cloud;
}

TEST(RoughForegroundMap, AClosedShellOfVisitorsIsSeenFullyInEveryDirection) {
  const vec3 centre(0.0f, 0.3f, 0.0f);
  VoxelGrid grid;
  grid.build(sphereCap(centre, 0.6f, vec3(0, 1, 0), 4.0f, vec3(0.2f, 0.5f, 0.8f)));
  RoughForegroundMap map(64, {0.6f, 0.8f});
  map.build(grid, centre);
  EXPECT_GT(map.coveredTexels(), std::size_t(0.95 * 64 * 32));
  // The lobe integral is normalised over the sphere: a covered sphere gives weight 1 and its colour.
  for (const float r : {0.6f, 0.8f})
    for (const vec3& d : {vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(-0.3f, 0.2f, 0.9f)}) {
      const ForegroundSample s = map.lookup(d, r);
      EXPECT_NEAR(s.weight, 1.0f, 0.03f) << r;
      EXPECT_NEAR(s.radiance.g, 0.5f, 0.02f) << r;
    }
}

TEST(RoughForegroundMap, AVisitorOnOneSideFadesWithTheLobeAndWidensWithRoughness) {
  const vec3 centre(0.0f, 0.3f, 0.0f);
  VoxelGrid grid;
  // A visitor-sized cap 0.6 m away along +X, 25 degrees in radius.
  grid.build(sphereCap(centre, 0.6f, vec3(1, 0, 0), 0.44f, vec3(1.0f)));
  RoughForegroundMap map(64, {0.5f, 0.9f});
  map.build(grid, centre);
  const float towards = map.lookup(vec3(1, 0, 0), 0.5f).weight;
  const float beside = map.lookup(vec3(0.5f, 0, 0.866f), 0.5f).weight;  // 60 degrees off
  const float away = map.lookup(vec3(-1, 0, 0), 0.5f).weight;
  EXPECT_GT(towards, 0.3f);
  EXPECT_LT(towards, 1.0f);  // the lobe reaches past the cap's edge
  EXPECT_GT(towards, beside);
  EXPECT_LT(away, 0.01f);
  // Rougher: lower at the centre, higher far off (the same light spread wider).
  EXPECT_LT(map.lookup(vec3(1, 0, 0), 0.9f).weight, towards);
  EXPECT_GT(map.lookup(vec3(0.5f, 0, 0.866f), 0.9f).weight, beside);
}

TEST(RoughForegroundMap, EmptyGridAndBadDirectionsGiveNothingAndBadSizesAreRejected) {
  VoxelGrid grid;
  RoughForegroundMap map(16, {0.7f});
  map.build(grid, vec3(0.0f));
  EXPECT_EQ(map.coveredTexels(), 0u);
  EXPECT_EQ(map.lookup(vec3(0, 1, 0), 0.7f).weight, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(map.lookup(vec3(nan, 0, 0), 0.7f).weight, 0.0f);
  EXPECT_EQ(map.lookup(vec3(0.0f), 0.7f).weight, 0.0f);
  EXPECT_THROW(RoughForegroundMap(7, {0.7f}), InputError);
  EXPECT_THROW(RoughForegroundMap(64, {}), InputError);
}

}  // namespace
}  // namespace holo::reflect
