#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/gltf_io.hpp"
#include "holo/core/mesh.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

// The unit square in z = 0 facing +Z, uv = (x, y) unless told otherwise.
TriangleMesh square(std::vector<vec2> uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.uvs = std::move(uvs);
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.computeNormals();
  return m;
}

void expectFiniteFrames(const TriangleMesh& m) {
  ASSERT_EQ(m.tangents.size(), m.positions.size());
  for (std::size_t i = 0; i < m.tangents.size(); ++i) {
    const vec4& t = m.tangents[i];
    ASSERT_TRUE(isFinite(vec3(t))) << "vertex " << i;
    EXPECT_NEAR(glm::length(vec3(t)), 1.0f, 1e-4f) << "vertex " << i;
    EXPECT_NEAR(glm::dot(vec3(t), m.normals[i]), 0.0f, 1e-4f) << "vertex " << i;
    EXPECT_EQ(std::abs(t.w), 1.0f) << "vertex " << i;
  }
}

// dP/du is +X and dP/dv is +Y: the tangent is exactly +X and the frame right-handed.
TEST(Tangents, FlatQuadGetsTheExactTangent) {
  TriangleMesh m = square();
  m.computeTangents();
  for (const vec4& t : m.tangents) EXPECT_LT(glm::length(t - vec4(1, 0, 0, 1)), 1e-6f);
  // The same from the second uv set, with u running along +Y and v along +X: mirrored.
  m.uvs1 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  m.computeTangents(1);
  for (const vec4& t : m.tangents) EXPECT_LT(glm::length(t - vec4(0, 1, 0, -1)), 1e-6f);
}

TEST(Tangents, MirroredUvsFlipHandedness) {
  TriangleMesh m = square({{1, 0}, {0, 0}, {0, 1}, {1, 1}});  // u = 1 - x
  m.computeTangents();
  for (const vec4& t : m.tangents) EXPECT_LT(glm::length(t - vec4(-1, 0, 0, -1)), 1e-6f);
  // The bitangent w * cross(n, t) still follows +v.
  const vec3 bitangent = m.tangents[0].w * glm::cross(m.normals[0], vec3(m.tangents[0]));
  EXPECT_LT(glm::length(bitangent - vec3(0, 1, 0)), 1e-6f);
}

// Zero-area uv triangles (all corners at one uv, or collinear uvs) and a triangle with no area
// say nothing about the tangent: every vertex still gets a finite unit frame.
TEST(Tangents, DegenerateUvsAndTrianglesStayFinite) {
  TriangleMesh same = square({{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}});
  same.computeTangents();
  expectFiniteFrames(same);
  TriangleMesh collinear = square({{0, 0}, {1, 1}, {2, 2}, {3, 3}});
  collinear.computeTangents();
  expectFiniteFrames(collinear);
  TriangleMesh no_uvs = square({});
  no_uvs.computeTangents();
  expectFiniteFrames(no_uvs);
  TriangleMesh sliver;
  sliver.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  sliver.uvs = {{0, 0}, {1, 0}, {0, 1}};
  sliver.triangles = {{0, 1, 2}};
  sliver.computeNormals();
  sliver.computeTangents();
  expectFiniteFrames(sliver);
  // Normals along -Z (the branch of the fallback frame that divides by 1 + n.z).
  TriangleMesh down = square({});
  for (auto& n : down.normals) n = vec3(0, 0, -1);
  down.computeTangents();
  expectFiniteFrames(down);
}

// A mirroring transform keeps the bitangent following +v: w flips with the determinant.
TEST(Tangents, MirroringTransformFlipsHandedness) {
  TriangleMesh m = square();
  m.computeTangents();
  m.transform(glm::scale(mat4(1.0f), vec3(-1, 1, 1)));
  for (std::size_t i = 0; i < m.tangents.size(); ++i) {
    EXPECT_LT(glm::length(vec3(m.tangents[i]) - vec3(-1, 0, 0)), 1e-6f);
    EXPECT_EQ(m.tangents[i].w, -1.0f);
    const vec3 bitangent = m.tangents[i].w * glm::cross(m.normals[i], vec3(m.tangents[i]));
    EXPECT_LT(glm::length(bitangent - vec3(0, 1, 0)), 1e-6f);
  }
}

// The Khronos clearcoat relic (a normal map and a clearcoat normal map) and glass relic (textured)
// come without TANGENT: the loader generates unit tangents orthogonal to the normals.
TEST(Tangents, GeneratedForTheKhronosModelsWithNormalMaps) {
  HOLO_REQUIRE_SHARED_DATA("models/khronos_clearcoat_wicker.glb");
  HOLO_REQUIRE_SHARED_DATA("models/khronos_glass_hurricane_candle_holder.glb");
  for (const char* file :
       {"models/khronos_clearcoat_wicker.glb", "models/khronos_glass_hurricane_candle_holder.glb"}) {
    SCOPED_TRACE(file);
    const Model model = loadGltf(test::sharedData(file));
    ASSERT_FALSE(model.meshes.empty());
    for (const auto& mesh : model.meshes) expectFiniteFrames(mesh);
  }
}

}  // namespace
}  // namespace holo
