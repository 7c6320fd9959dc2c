#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/relics/relics.hpp"
#include "shared_data.hpp"

namespace holo::relics {
namespace {

// Procedural relics are written as glTF and loaded back through the same loader, unchanged.
TEST(Relics, RoundTripThroughGlb) {
  const auto dir = test::scratchDir("sim_relics");
  for (const auto& name : relicNames()) {
    SCOPED_TRACE(name);
    const Model made = makeRelic(name);
    saveGltf(dir / (name + ".glb"), made);
    const Model back = loadGltf(dir / (name + ".glb"));
    ASSERT_EQ(back.meshes.size(), made.meshes.size());
    EXPECT_EQ(back.triangleCount(), made.triangleCount());
    EXPECT_LT(glm::length(back.bounds().lo - made.bounds().lo), 1e-6f);
    EXPECT_LT(glm::length(back.bounds().hi - made.bounds().hi), 1e-6f);
    ASSERT_EQ(back.materials.size(), made.materials.size());
    EXPECT_FLOAT_EQ(back.materials[0].roughness, made.materials[0].roughness);
    EXPECT_FLOAT_EQ(back.materials[0].metallic, made.materials[0].metallic);
    EXPECT_FLOAT_EQ(back.materials[0].specular, made.materials[0].specular);  // the Lambert bowl's 0
    EXPECT_FLOAT_EQ(back.materials[0].transmission, made.materials[0].transmission);
    EXPECT_FLOAT_EQ(back.materials[0].ior, made.materials[0].ior);
    EXPECT_FLOAT_EQ(back.materials[0].thickness, made.materials[0].thickness);
    EXPECT_FLOAT_EQ(back.materials[0].attenuation_distance, made.materials[0].attenuation_distance);
  }
}

// A volume (KHR_materials_volume) needs a closed surface wound counter-clockwise from outside:
// with positions welded, every edge is shared by exactly two triangles that run it in opposite
// directions, and the signed volume (divergence theorem) is positive.
void expectClosedOutwardSolid(const Model& relic) {
  std::map<std::array<float, 3>, int> weld;
  auto id = [&](const vec3& p) {
    const std::array<float, 3> key{std::round(p.x * 1e5f), std::round(p.y * 1e5f), std::round(p.z * 1e5f)};
    return weld.emplace(key, static_cast<int>(weld.size())).first->second;
  };
  std::map<std::pair<int, int>, int> directed;
  double volume = 0.0;
  for (const auto& mesh : relic.meshes)
    for (const auto& t : mesh.triangles) {
      const vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
      volume += glm::dot(glm::dvec3(a), glm::cross(glm::dvec3(b), glm::dvec3(c))) / 6.0;
      const int ia = id(a), ib = id(b), ic = id(c);
      if (ia == ib || ib == ic || ia == ic) continue;  // a lathe's pole: zero area
      ++directed[{ia, ib}];
      ++directed[{ib, ic}];
      ++directed[{ic, ia}];
    }
  int unmatched = 0;
  for (const auto& [edge, count] : directed) {
    const auto back = directed.find({edge.second, edge.first});
    if (count != 1 || back == directed.end() || back->second != 1) ++unmatched;
  }
  EXPECT_EQ(unmatched, 0);
  EXPECT_GT(volume, 0.0);
}

TEST(Relics, GlassRelicsAreClosedOutwardSolids) {
  for (const std::string name : {"glass-vase", "crystal"}) {
    SCOPED_TRACE(name);
    const Model relic = makeRelic(name);
    ASSERT_EQ(relic.materials.size(), 1u);
    const Material& m = relic.materials[0];
    EXPECT_EQ(m.transmission, 1.0f);
    EXPECT_GT(m.thickness, 0.0f);  // a volume, not thin-walled
    EXPECT_TRUE(std::isfinite(m.attenuation_distance));
    EXPECT_FLOAT_EQ(m.ior, name == "crystal" ? 2.42f : 1.5f);
    expectClosedOutwardSolid(relic);
  }
}

// The bowls: one thick closed solid, open at the top: a ray straight down the axis meets the inner
// floor well above the base, one down through the wall's middle meets the wall's top surface.
TEST(Relics, BowlsAreThickOpenSolids) {
  for (const std::string name : {"bowl", "metal-bowl"}) {
    SCOPED_TRACE(name);
    const Model relic = makeRelic(name);
    expectClosedOutwardSolid(relic);
    RayScene scene;
    for (const auto& mesh : relic.meshes) scene.addMesh(mesh);
    scene.commit();
    const Bounds3 b = relic.bounds();
    const RayHit floor = scene.intersect({{0.0f, 1.0f, 0.0f}, {0, -1, 0}});
    ASSERT_TRUE(floor.hit());
    const float floor_y = 1.0f - floor.t;
    EXPECT_GT(floor_y, 0.1f * b.hi.y);       // the floor stands on a thick base
    EXPECT_LT(floor_y, 0.4f * b.hi.y);       // and the inside is deep
    EXPECT_GT(b.extent().x, 1.5f * b.hi.y);  // wider than tall: a bowl
  }
  const Material& clay = makeRelic("bowl").materials.at(0);
  EXPECT_FLOAT_EQ(clay.specular, 0.0f);  // Lambert: no reflection lobe
  EXPECT_FLOAT_EQ(clay.metallic, 0.0f);
  const Material& metal = makeRelic("metal-bowl").materials.at(0);
  EXPECT_FLOAT_EQ(metal.metallic, 1.0f);
  EXPECT_FLOAT_EQ(metal.roughness, 0.4f);
}

TEST(Relics, MaterialsSpanMirrorToRoughMetal) {
  EXPECT_FLOAT_EQ(makeRelic("sphere").materials[0].roughness, 0.0f);
  EXPECT_FLOAT_EQ(makeRelic("tripod").materials[0].roughness, 0.6f);
}

TEST(Relics, SizeAndPlacement) {
  for (const auto& name : relicNames()) {
    SCOPED_TRACE(name);
    const Bounds3 b = makeRelic(name).bounds();
    EXPECT_NEAR(b.lo.y, 0.0f, 1e-4f);
    // As tall as allowed, unless it would be too wide.
    const float width = std::max(b.extent().x, b.extent().z);
    EXPECT_LE(b.hi.y, kRelicHeight + 1e-4f);
    EXPECT_LE(width, kRelicMaxWidth + 1e-4f);
    EXPECT_TRUE(std::abs(b.hi.y - kRelicHeight) < 1e-4f || std::abs(width - kRelicMaxWidth) < 1e-4f);
    EXPECT_NEAR(b.center().x, 0.0f, 0.05f);
  }
}

// The kettle is not convex: a ray through the gap between the handle and the body escapes, while
// a ray through the body and one through the handle both hit.
TEST(Relics, KettleHandleLeavesAGap) {
  RayScene scene;
  for (const auto& mesh : makeRelic("kettle").meshes) scene.addMesh(mesh);
  scene.commit();
  auto hits = [&](float x, float y) { return scene.intersect({{x, y, -1.0f}, {0, 0, 1}}).hit(); };
  EXPECT_TRUE(hits(0.0f, 0.08f));      // body
  EXPECT_TRUE(hits(-0.165f, 0.10f));   // far side of the handle loop
  EXPECT_FALSE(hits(-0.135f, 0.10f));  // inside the loop
}

TEST(Relics, FitOnPedestalScalesAnyModel) {
  Model m = makeRelic("vase");
  for (auto& mesh : m.meshes)
    for (auto& p : mesh.positions) p = 10.0f * p + vec3(3, -2, 1);
  fitOnPedestal(m);
  const Bounds3 b = m.bounds();
  EXPECT_NEAR(b.lo.y, 0.0f, 1e-4f);
  EXPECT_NEAR(b.hi.y, kRelicHeight, 1e-4f);
  EXPECT_NEAR(b.center().x, 0.0f, 1e-4f);
  EXPECT_NEAR(b.center().z, 0.0f, 1e-4f);
  Model empty;
  EXPECT_NO_THROW(fitOnPedestal(empty));
  EXPECT_THROW(makeRelic("urn"), InputError);
}

}  // namespace
}  // namespace holo::relics
