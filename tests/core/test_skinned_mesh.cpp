#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "base64.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/skinned_mesh.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

namespace fs = std::filesystem;
using test::base64;

// Builds a .gltf with one embedded buffer: each accessor gets its own buffer view.
struct GltfWriter {
  std::string buffer;
  std::string views, accessors;
  int count = 0;

  template <class T>
  int add(const std::vector<T>& data, int component_type, const char* type, std::size_t elements) {
    while (buffer.size() % 4) buffer += '\0';
    const std::size_t offset = buffer.size();
    buffer.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T));
    const std::string sep = count ? "," : "";
    views += sep + "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
             ",\"byteLength\":" + std::to_string(data.size() * sizeof(T)) + "}";
    accessors += sep + "{\"bufferView\":" + std::to_string(count) +
                 ",\"componentType\":" + std::to_string(component_type) +
                 ",\"count\":" + std::to_string(elements) + ",\"type\":\"" + type + "\"}";
    return count++;
  }

  std::string json(const std::string& rest) const {
    return "{\"asset\":{\"version\":\"2.0\"}," + rest + ",\"bufferViews\":[" + views + "],\"accessors\":[" +
           accessors + "],\"buffers\":[{\"byteLength\":" + std::to_string(buffer.size()) +
           ",\"uri\":\"data:application/octet-stream;base64," + base64(buffer) + "\"}]}";
  }
};

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;

// A 2-joint skin: joint 0 (node 0) at the origin, joint 1 (node 1, its child) at (0, 1, 0).
// Vertices (0,0,0) on joint 0, (0,1,0) and (0,2,0) on joint 1, (1,1,0) half and half.
// Clip 0: joint 1 turns about +Z from 0 to 90 degrees over 1 s (LINEAR); joint 0 jumps to x = 3
// at 0.75 s (STEP). Clip 1: joint 0 moves to x = 1 over 1 s on a cubic spline whose first key
// leaves with slope 2 m/s.
struct TinySkin {
  std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0};
  std::vector<std::uint8_t> joints = {0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0};
  std::vector<float> inverse_bind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,
                                     1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};

  fs::path write(const std::string& name) const {
    GltfWriter w;
    const std::vector<float> positions = {0, 0, 0, 0, 1, 0, 0, 2, 0, 1, 1, 0};
    const std::vector<std::uint16_t> indices = {0, 3, 1, 1, 3, 2};
    const int pos = w.add(positions, kFloat, "VEC3", 4);
    const int idx = w.add(indices, kUShort, "SCALAR", 6);
    const int jnt = w.add(joints, kUByte, "VEC4", 4);
    const int wgt = w.add(weights, kFloat, "VEC4", 4);
    const int ibm = w.add(inverse_bind, kFloat, "MAT4", 2);
    const float s = std::sqrt(0.5f);
    const int rot_t = w.add(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
    const int rot_v = w.add(std::vector<float>{0, 0, 0, 1, 0, 0, s, s}, kFloat, "VEC4", 2);
    const int step_t = w.add(std::vector<float>{0, 0.75f}, kFloat, "SCALAR", 2);
    const int step_v = w.add(std::vector<float>{0, 0, 0, 3, 0, 0}, kFloat, "VEC3", 2);
    const int cub_t = w.add(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
    // in-tangent, value, out-tangent per key
    const int cub_v =
        w.add(std::vector<float>{0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0}, kFloat, "VEC3", 6);
    auto n = [](int i) { return std::to_string(i); };
    const std::string rest =
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,2]}],"
        "\"nodes\":[{\"name\":\"root\",\"children\":[1]},{\"name\":\"tip\",\"translation\":[0,1,0]},"
        "{\"name\":\"body\",\"mesh\":0,\"skin\":0,\"translation\":[5,5,5]}],"
        "\"skins\":[{\"joints\":[0,1],\"inverseBindMatrices\":" +
        n(ibm) +
        "}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" +
        n(pos) + ",\"JOINTS_0\":" + n(jnt) + ",\"WEIGHTS_0\":" + n(wgt) + "},\"indices\":" + n(idx) +
        "}]}],"
        "\"animations\":[{\"name\":\"bend\",\"samplers\":[{\"input\":" +
        n(rot_t) + ",\"output\":" + n(rot_v) + ",\"interpolation\":\"LINEAR\"},{\"input\":" + n(step_t) +
        ",\"output\":" + n(step_v) +
        ",\"interpolation\":\"STEP\"}],"
        "\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"rotation\"}},"
        "{\"sampler\":1,\"target\":{\"node\":0,\"path\":\"translation\"}}]},"
        "{\"name\":\"slide\",\"samplers\":[{\"input\":" +
        n(cub_t) + ",\"output\":" + n(cub_v) +
        ",\"interpolation\":\"CUBICSPLINE\"}],"
        "\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}]}]";
    const fs::path dir = test::scratchDir("skinned_" + name);
    const fs::path path = dir / (name + ".gltf");
    std::ofstream(path) << w.json(rest);
    return path;
  }
};

void expectNear(const vec3& a, const vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(SkinnedMesh, TwoJointSkinPosesAsComputedByHand) {
  const SkinnedModel model = loadSkinnedGltf(TinySkin{}.write("tiny"));
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.clips.size(), 2u);
  EXPECT_EQ(model.clips[0].name, "bend");
  EXPECT_FLOAT_EQ(model.clips[0].duration, 1.0f);
  EXPECT_EQ(model.clips[1].channels[0].interpolation, Interpolation::cubic_spline);
  // Rest pose: the skinned node's own translation (5,5,5) is ignored, as glTF asks.
  const Model rest = poseSkinned(model, -1, 0.0f);
  expectNear(rest.meshes[0].positions[2], {0, 2, 0});
  expectNear(rest.meshes[0].positions[3], {1, 1, 0});
  // t = 0.5: joint 1 at 45 degrees, the step channel still at its first key.
  const float s = std::sqrt(0.5f);
  const Model half = poseSkinned(model, 0, 0.5f);
  expectNear(half.meshes[0].positions[0], {0, 0, 0});
  expectNear(half.meshes[0].positions[1], {0, 1, 0});
  expectNear(half.meshes[0].positions[2], {-s, 1 + s, 0});
  expectNear(half.meshes[0].positions[3], 0.5f * vec3(1, 1, 0) + 0.5f * vec3(s, 1 + s, 0));
  // t = 1: 90 degrees, and the step channel has jumped the whole skeleton to x = 3.
  const Model end = poseSkinned(model, 0, 1.0f);
  expectNear(end.meshes[0].positions[2], {3 - 1, 1, 0});
  expectNear(end.meshes[0].positions[3], {3 + 0.5f, 1.5f, 0});
  // Normals follow the skinned surface: the triangles stay in the z = 0 plane.
  for (const vec3& n : end.meshes[0].normals) EXPECT_NEAR(std::abs(n.z), 1.0f, 1e-5f);
  // Cubic spline: Hermite with slope 2 leaving key 0 and 0 arriving at key 1 gives 0.75 at s = 0.5.
  const Model slide = poseSkinned(model, 1, 0.5f);
  expectNear(slide.meshes[0].positions[0], {0.75f, 0, 0});
  expectNear(poseSkinned(model, 1, 5.0f).meshes[0].positions[0], {1, 0, 0});  // clamped
}

TEST(SkinnedMesh, BadSkinDataIsAnInputErrorNamingFileAndField) {
  const auto expectError = [](const TinySkin& skin, const std::string& name, const std::string& field) {
    const fs::path path = skin.write(name);
    try {
      loadSkinnedGltf(path);
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
    }
  };
  TinySkin joint_out_of_range;
  joint_out_of_range.joints[4] = 7;
  expectError(joint_out_of_range, "joint_range", "JOINTS_0");
  TinySkin bad_sum;
  bad_sum.weights[12] = 0.2f;
  expectError(bad_sum, "weight_sum", "WEIGHTS_0");
  TinySkin nan_weight;
  nan_weight.weights[1] = std::nanf("");
  expectError(nan_weight, "weight_nan", "WEIGHTS_0");
  TinySkin nan_matrix;
  nan_matrix.inverse_bind[20] = std::nanf("");
  expectError(nan_matrix, "ibm_nan", "inverseBindMatrices");
}

TEST(SkinnedMesh, ChannelSamplingFollowsTheSpecification) {
  AnimationChannel c;
  c.path = AnimationPath::rotation;
  c.times = {0.0f, 2.0f};
  // Keys 350 degrees apart the long way: slerp takes the 10-degree short arc through -q.
  const float a = glm::radians(175.0f);
  c.values = {vec4(0, 0, 0, 1), vec4(0, std::sin(a), 0, std::cos(a))};
  const vec4 mid = sampleChannel(c, 1.0f);
  EXPECT_NEAR(glm::length(mid), 1.0f, 1e-5f);
  EXPECT_GT(std::abs(mid.w), 0.7f);  // quarter of 350 is far from identity; half of the 10-degree arc is not
  c.interpolation = Interpolation::step;
  EXPECT_EQ(sampleChannel(c, 1.999f), c.values[0]);
  EXPECT_EQ(sampleChannel(c, 2.0f), c.values[1]);
  EXPECT_EQ(sampleChannel(c, -1.0f), c.values[0]);
}

// The two real skinned figures (COLLADA2GLTF exports, walking cycles).
class RealFigure : public ::testing::TestWithParam<const char*> {};

TEST_P(RealFigure, LoadsPosesAndMovesItsLimbs) {
  const std::string relative = std::string("models/humans/") + GetParam();
  HOLO_REQUIRE_SHARED_DATA(relative);
  const fs::path path = test::sharedData(relative);
  const SkinnedModel model = loadSkinnedGltf(path);
  ASSERT_FALSE(model.meshes.empty());
  ASSERT_EQ(model.clips.size(), 1u);
  EXPECT_GT(model.clips[0].duration, 0.5f);
  ASSERT_GE(model.meshes[0].skin, 0);
  EXPECT_EQ(model.skeleton.skins[0].joints.size(), 19u);
  for (const vec4& w : model.meshes[0].weights) EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-5f);

  // Bind pose: skinning with the rest skeleton gives the unskinned mesh back.
  const Model unskinned = loadGltf(path);
  const Model rest = poseSkinned(model, -1, 0.0f);
  ASSERT_EQ(rest.meshes[0].positions.size(), unskinned.meshes[0].positions.size());
  float worst = 0.0f;
  for (std::size_t i = 0; i < rest.meshes[0].positions.size(); ++i)
    worst = std::max(worst, glm::length(rest.meshes[0].positions[i] - unskinned.meshes[0].positions[i]));
  EXPECT_LT(worst, 1e-3f) << "metres";

  // A human-sized figure, upright (+Y), in every frame of the walk.
  const float duration = model.clips[0].duration;
  std::vector<Model> frames;
  for (int k = 0; k < 4; ++k)
    frames.push_back(poseSkinned(model, 0, duration * static_cast<float>(k) / 4.0f));
  for (const Model& f : frames) {
    const Bounds3 b = f.bounds();
    const vec3 size = b.hi - b.lo;
    EXPECT_GT(size.y, 1.2f);
    EXPECT_LT(size.y, 2.1f);
    EXPECT_LT(std::max(size.x, size.z), size.y);
  }
  // Limbs move: the lowest vertices (the feet) travel between frames, by centimetres at least.
  float largest = 0.0f;
  for (std::size_t i = 0; i < frames[0].meshes[0].positions.size(); ++i)
    largest =
        std::max(largest, glm::length(frames[0].meshes[0].positions[i] - frames[2].meshes[0].positions[i]));
  EXPECT_GT(largest, 0.1f);
}

INSTANTIATE_TEST_SUITE_P(Humans, RealFigure, ::testing::Values("cesium_man.glb", "rigged_figure.glb"));

}  // namespace
}  // namespace holo
