#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/core/shapes.hpp"

namespace holo {
namespace {

TriangleMesh quad(float z) {
  TriangleMesh m;
  m.positions = {{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(RayScene, HitsNearestMeshAndReportsIt) {
  RayScene scene;
  const auto far_id = scene.addMesh(quad(5));
  const auto near_id = scene.addMesh(quad(2));
  scene.commit();
  const RayHit hit = scene.intersect({{0.2f, 0.1f, 0}, {0, 0, 1}});
  ASSERT_TRUE(hit.hit());
  EXPECT_EQ(hit.geometry, near_id);
  EXPECT_NEAR(hit.t, 2.0f, 1e-5f);
  EXPECT_NEAR(hit.geometric_normal.z, -1.0f, 1e-6f);  // faces the ray
  EXPECT_FALSE(scene.intersect({{0.2f, 0.1f, 0}, {0, 0, -1}}).hit());
  EXPECT_TRUE(scene.occluded({{0, 0, 0}, {0, 0, 1}}, 0.0f, 3.0f));
  EXPECT_FALSE(scene.occluded({{0, 0, 0}, {0, 0, 1}}, 0.0f, 1.5f));
  const RayHit from_between = scene.intersect({{0, 0, 3}, {0, 0, 1}});
  EXPECT_EQ(from_between.geometry, far_id);
}

TEST(RayScene, HitOpacityPassesCutOutHitsAndStopsPartialOnesByMode) {
  // Two quads: the near one is cut out where x < 0 and half opaque where x >= 0.
  RayScene scene;
  const auto near_id = scene.addMesh(quad(2));
  const auto far_id = scene.addMesh(quad(5));
  scene.setHitOpacity(near_id, [](const Ray& ray, const RayHit& hit) {
    return (ray.origin + hit.t * ray.direction).x < 0.0f ? 0.0f : 0.5f;
  });
  scene.commit();
  // Cut out: every query goes through to the far quad.
  EXPECT_EQ(scene.intersect({{-0.5f, 0, 0}, {0, 0, 1}}).geometry, far_id);
  EXPECT_EQ(scene.intersect({{-0.5f, 0, 0}, {0, 0, 1}}, 0.0f, 1e30f, PartialHits::Solid).geometry, far_id);
  EXPECT_FALSE(scene.occluded({{-0.5f, 0, 0}, {0, 0, 1}}, 0.0f, 3.0f));
  // Half opaque: Solid always stops; Stochastic stops about half of many distinct rays, and the
  // same ray always decides alike.
  int stopped = 0, occluded = 0;
  constexpr int kRays = 2000;
  for (int i = 0; i < kRays; ++i) {
    const Ray ray{{0.5f + 0.4f * float(i) / kRays, 0.1f, 0}, {0, 0, 1}};
    EXPECT_EQ(scene.intersect(ray, 0.0f, 1e30f, PartialHits::Solid).geometry, near_id);
    const bool stops = scene.intersect(ray).geometry == near_id;
    EXPECT_EQ(stops, scene.intersect(ray).geometry == near_id);
    stopped += stops ? 1 : 0;
    occluded += scene.occluded(ray, 0.0f, 3.0f) ? 1 : 0;
  }
  EXPECT_NEAR(double(stopped) / kRays, 0.5, 0.05);
  EXPECT_NEAR(double(occluded) / kRays, 0.5, 0.05);
}

// Packets give what single rays give: a fan of rays from one eye over a sphere in front of a
// half-opaque quad, in a count that is no multiple of either packet width, in both partial modes,
// with either coherence flag (the fan shuffled for the incoherent one) and at both widths.
TEST(RayScene, PacketsHitWhatSingleRaysHit) {
  RayScene scene;
  scene.addMesh(makeSphere(0.6f, 16, 32));
  TriangleMesh backdrop = quad(3);
  for (vec3& p : backdrop.positions) p *= vec3(3, 3, 1);  // wider than the fan at its distance
  const auto quad_id = scene.addMesh(backdrop);
  scene.setHitOpacity(quad_id, [](const Ray&, const RayHit&) { return 0.5f; });
  scene.commit();
  std::vector<Ray> rays;
  for (int y = 0; y < 37; ++y)
    for (int x = 0; x < 29; ++x)
      rays.push_back(
          {{0, 0, -3}, glm::normalize(vec3(-0.4f + 0.8f * x / 28.0f, -0.4f + 0.8f * y / 36.0f, 1.0f))});
  ASSERT_NE(rays.size() % 8, 0u);
  ASSERT_NE(rays.size() % 16, 0u);
  const std::vector<Ray> fan = rays;
  std::vector<Ray> shuffled = rays;
  std::mt19937 rng(7);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  for (const int width : {8, 16})
    for (const RayCoherence coherence : {RayCoherence::Coherent, RayCoherence::Incoherent})
      for (const PartialHits partial : {PartialHits::Stochastic, PartialHits::Solid}) {
        SCOPED_TRACE(width);
        scene.setPacketWidth(width);
        rays = coherence == RayCoherence::Incoherent ? shuffled : fan;
        std::vector<RayHit> packed(rays.size());
        scene.intersectPackets(rays, packed, coherence, 0.0f, 1e30f, partial);
        int sphere_hits = 0, quad_hits = 0, misses = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
          const RayHit single = scene.intersect(rays[i], 0.0f, 1e30f, partial);
          ASSERT_EQ(packed[i].geometry, single.geometry) << "ray " << i;
          if (!single.hit()) {
            ++misses;
            continue;
          }
          (single.geometry == quad_id ? quad_hits : sphere_hits) += 1;
          EXPECT_EQ(packed[i].primitive, single.primitive) << "ray " << i;
          EXPECT_NEAR(packed[i].t, single.t, 1e-5f * single.t) << "ray " << i;
          EXPECT_NEAR(packed[i].barycentric.x, single.barycentric.x, 1e-5f) << "ray " << i;
          EXPECT_NEAR(packed[i].barycentric.y, single.barycentric.y, 1e-5f) << "ray " << i;
          EXPECT_GT(glm::dot(packed[i].geometric_normal, single.geometric_normal), 0.9999f) << "ray " << i;
        }
        EXPECT_GT(sphere_hits, 100);
        EXPECT_GT(quad_hits, 100);
        if (partial == PartialHits::Stochastic) {
          EXPECT_GT(misses, 50);  // rays that passed the quad
        }
      }
  std::vector<RayHit> too_few(3);
  EXPECT_THROW(scene.intersectCoherent(rays, too_few), Error);
  EXPECT_THROW(scene.setPacketWidth(4), Error);
  EXPECT_EQ(RayScene().packetWidth(), RayScene::nativePacketWidth());
}

TEST(RayScene, DegenerateTrianglesAreNeverHitAndAxisRaysWork) {
  TriangleMesh m = quad(1);
  m.positions.push_back({0, 0, 0.5f});
  m.triangles.push_back({4, 4, 4});  // a point
  m.triangles.push_back({0, 4, 0});  // a line
  RayScene scene;
  scene.addMesh(m);
  scene.commit();
  for (const vec3 dir : {vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(-0.0f, 0.0f, 1)}) {
    const RayHit hit = scene.intersect({{0, 0, 0}, dir});
    if (hit.hit()) {
      EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
      EXPECT_TRUE(isFinite(hit.geometric_normal));
    }
  }
  EXPECT_TRUE(scene.intersect({{0, 0, 0}, {0, 0, 1}}).hit());
}

TEST(RayScene, UpdatedPositionsMoveTheMesh) {
  RayScene scene;
  const auto id = scene.addMesh(quad(2));
  scene.commit();
  std::vector<vec3> moved = scene.mesh(id).positions;
  for (auto& p : moved) p.z = 4;
  scene.updatePositions(id, moved);
  scene.commit();
  EXPECT_NEAR(scene.intersect({{0, 0, 0}, {0, 0, 1}}).t, 4.0f, 1e-5f);
}

TEST(RayScene, ShadingNormalInterpolatesAndFacesRay) {
  TriangleMesh m = quad(2);
  m.computeNormals();
  RayScene scene;
  scene.addMesh(m);
  scene.commit();
  const Ray ray{{0.3f, 0.3f, 0}, {0, 0, 1}};
  const RayHit hit = scene.intersect(ray);
  const vec3 n = scene.shadingNormal(hit, ray.direction);
  EXPECT_NEAR(n.z, -1.0f, 1e-6f);
}

}  // namespace
}  // namespace holo
