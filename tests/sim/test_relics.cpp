#include <gtest/gtest.h>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/sim/relics.hpp"
#include "shared_data.hpp"

namespace holo::sim {
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
    EXPECT_FLOAT_EQ(back.materials[0].metallic, 1.0f);
  }
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
}  // namespace holo::sim
