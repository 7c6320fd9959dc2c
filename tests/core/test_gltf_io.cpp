#include <gtest/gtest.h>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "base64.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

namespace fs = std::filesystem;
using test::base64;

template <class T>
std::string bytesOf(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// One triangle (0,0,0) (1,0,0) (0,1,0) as positions (36 bytes) then uint16 indices (6 bytes).
struct TriangleFile {
  std::vector<float> positions{0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<std::uint16_t> indices{0, 1, 2};
  std::string mode = "4";
  std::string node = R"({"mesh": 0})";
  std::string extra_nodes;
  std::string buffer_uri;  // empty: embedded data URI
  std::string extensions_required;
  std::string material = R"({"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0],
      "metallicFactor": 0.75, "roughnessFactor": 0.3}, "emissiveFactor": [1.0, 0.5, 0.0]})";

  std::string json() const {
    const std::string data = bytesOf(positions) + bytesOf(indices);
    const std::string uri =
        buffer_uri.empty() ? "data:application/octet-stream;base64," + base64(data) : buffer_uri;
    const std::size_t pos_bytes = positions.size() * 4;
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [)" +
           node + extra_nodes + R"(],
  "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": )" +
           mode + R"(, "material": 0}]}],
  "materials": [)" +
           material + R"(],
  "buffers": [{"byteLength": )" +
           std::to_string(data.size()) + R"(, "uri": ")" + uri + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" +
           std::to_string(pos_bytes) + R"(},
                  {"buffer": 0, "byteOffset": )" +
           std::to_string(pos_bytes) + R"(, "byteLength": )" + std::to_string(indices.size() * 2) + R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
           std::to_string(positions.size() / 3) +
           R"(, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                {"bufferView": 1, "componentType": 5123, "count": )" +
           std::to_string(indices.size()) + R"(, "type": "SCALAR"}])" + extensions_required + "}";
  }
};

fs::path write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Loading must fail with an InputError naming the file, and the message must mention `needle`.
void expectInputError(const fs::path& path, const std::string& needle) {
  try {
    loadGltf(path);
    ADD_FAILURE() << "expected InputError for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(GltfIo, LoadsTriangleWithMaterialAndComputesNormals) {
  const auto dir = test::scratchDir("gltf_ok");
  const Model m = loadGltf(write(dir / "tri.gltf", TriangleFile{}.json()));
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.triangleCount(), 1u);
  const TriangleMesh& mesh = m.meshes[0];
  ASSERT_EQ(mesh.normals.size(), 3u);  // none in the file: computed
  for (const vec3& n : mesh.normals) EXPECT_LT(glm::length(n - vec3(0, 0, 1)), 1e-5f);
  ASSERT_EQ(m.materials.size(), 1u);
  const Material& mat = m.materials[0];
  EXPECT_FLOAT_EQ(mat.base_colour.g, 0.4f);
  EXPECT_FLOAT_EQ(mat.metallic, 0.75f);
  EXPECT_FLOAT_EQ(mat.roughness, 0.3f);
  EXPECT_FLOAT_EQ(mat.emission.r, 1.0f);
  EXPECT_EQ(mat.base_colour_texture.index, -1);
}

TEST(GltfIo, AppliesTheNodeHierarchy) {
  const auto dir = test::scratchDir("gltf_nodes");
  TriangleFile f;
  // Parent: translate (10, 0, 0) and scale 2; child: rotate 90 degrees about Z, holds the mesh.
  f.node = R"({"children": [1], "translation": [10, 0, 0], "scale": [2, 2, 2]})";
  f.extra_nodes = R"(, {"mesh": 0, "rotation": [0, 0, 0.7071068, 0.7071068]})";
  const Model m = loadGltf(write(dir / "nodes.gltf", f.json()));
  ASSERT_EQ(m.meshes.size(), 1u);
  const auto& p = m.meshes[0].positions;
  EXPECT_LT(glm::length(p[0] - vec3(10, 0, 0)), 1e-5f);
  EXPECT_LT(glm::length(p[1] - vec3(10, 2, 0)), 1e-5f);  // (1,0,0) -> rotate -> (0,1,0) -> x2 + 10
  EXPECT_LT(glm::length(p[2] - vec3(8, 0, 0)), 1e-5f);   // (0,1,0) -> (-1,0,0)
  EXPECT_LT(glm::length(m.meshes[0].normals[0] - vec3(0, 0, 1)), 1e-5f);
}

TEST(GltfIo, MissingBufferNamesTheBuffer) {
  const auto dir = test::scratchDir("gltf_missing_buffer");
  TriangleFile f;
  f.buffer_uri = "missing.bin";
  expectInputError(write(dir / "missing.gltf", f.json()), "buffers");
}

TEST(GltfIo, IndexOutOfRange) {
  const auto dir = test::scratchDir("gltf_index");
  TriangleFile f;
  f.indices = {0, 1, 7};
  expectInputError(write(dir / "index.gltf", f.json()), "index 7");
}

TEST(GltfIo, NonTrianglePrimitive) {
  const auto dir = test::scratchDir("gltf_lines");
  TriangleFile f;
  f.mode = "1";  // LINES
  expectInputError(write(dir / "lines.gltf", f.json()), "mode 1");
}

TEST(GltfIo, DracoCompressedFile) {
  const auto dir = test::scratchDir("gltf_draco");
  TriangleFile f;
  f.extensions_required = R"(, "extensionsUsed": ["KHR_draco_mesh_compression"],
      "extensionsRequired": ["KHR_draco_mesh_compression"])";
  expectInputError(write(dir / "draco.gltf", f.json()), "KHR_draco_mesh_compression");
}

TEST(GltfIo, TruncatedBufferAndGarbage) {
  const auto dir = test::scratchDir("gltf_garbage");
  TriangleFile f;
  f.positions.resize(6);  // accessor still says 3 vertices: it overruns its buffer view
  std::string json = f.json();
  const auto at = json.find("\"count\": 2");
  ASSERT_NE(at, std::string::npos);
  json.replace(at, 10, "\"count\": 3");
  expectInputError(write(dir / "short.gltf", json), "accessors");
  expectInputError(write(dir / "junk.glb", "definitely not a glb file"), "glTF");
  expectInputError(write(dir / "junk.gltf", "{ not json"), "glTF");
  expectInputError(dir / "absent.glb", "not found");
  expectInputError(write(dir / "model.obj", "v 0 0 0"), ".obj");
}

TEST(GltfIo, NonFinitePositionsAreRejected) {
  const auto dir = test::scratchDir("gltf_nan");
  TriangleFile f;
  f.positions[4] = std::numeric_limits<float>::quiet_NaN();
  expectInputError(write(dir / "nan.gltf", f.json()), "POSITION");
}

// A degenerate triangle (all three corners equal) loads with finite unit normals (+Y by
// TriangleMesh::computeNormals' rule).
TEST(GltfIo, DegenerateTriangleGetsFiniteNormals) {
  const auto dir = test::scratchDir("gltf_degenerate");
  TriangleFile f;
  f.positions = {1, 1, 1, 1, 1, 1, 1, 1, 1};
  const Model m = loadGltf(write(dir / "flat.gltf", f.json()));
  for (const vec3& n : m.meshes[0].normals) EXPECT_LT(glm::length(n - vec3(0, 1, 0)), 1e-6f);
}

// A textured, emissive model written as .glb and read back: geometry, factors, the emission
// above 1 (KHR_materials_emissive_strength) and the texture pixels survive.
TEST(GltfIo, GlbRoundTripKeepsTexturesAndStrongEmission) {
  const auto dir = test::scratchDir("gltf_roundtrip");
  Model m;
  TriangleMesh mesh;
  mesh.name = "quad";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.computeNormals();
  m.meshes.push_back(mesh);
  Material mat;
  mat.name = "lamp";
  mat.roughness = 0.0f;
  mat.metallic = 1.0f;
  mat.emission = {12.0f, 6.0f, 3.0f};
  mat.base_colour_texture.index = 0;
  m.materials.push_back(mat);
  cv::Mat tex(4, 8, CV_8UC3, cv::Scalar(10, 20, 200));  // BGR: red
  tex.at<cv::Vec3b>(1, 2) = cv::Vec3b(255, 0, 0);
  m.textures.emplace_back(tex);
  saveGltf(dir / "quad.glb", m);
  const Model back = loadGltf(dir / "quad.glb");
  ASSERT_EQ(back.triangleCount(), 2u);
  ASSERT_EQ(back.meshes[0].uvs.size(), 4u);
  EXPECT_FLOAT_EQ(back.materials[0].roughness, 0.0f);
  EXPECT_NEAR(back.materials[0].emission.r, 12.0f, 1e-4f);
  EXPECT_NEAR(back.materials[0].emission.b, 3.0f, 1e-4f);
  ASSERT_EQ(back.materials[0].base_colour_texture.index, 0);
  ASSERT_EQ(back.textures.size(), 1u);
  EXPECT_EQ(cv::norm(back.textures[0].image(), tex, cv::NORM_INF), 0.0);
  // .gltf with everything embedded loads the same.
  saveGltf(dir / "quad.gltf", m);
  EXPECT_EQ(loadGltf(dir / "quad.gltf").triangleCount(), 2u);
  const auto bytes = encodeGlb(m);
  EXPECT_EQ(loadGlbFromMemory(bytes, "memory").triangleCount(), 2u);
}

// Replaces the first `from` in `json` with `to`.
std::string replaced(std::string json, const std::string& from, const std::string& to) {
  const auto at = json.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) json.replace(at, from.size(), to);
  return json;
}

// Counts come from the file: a claim of 2^62 elements in a 42-byte buffer is an InputError,
// never an allocation of exabytes (std::length_error) or an overflowed bounds check.
TEST(GltfIo, ElementCountsBeyondTheBufferAreRefusedBeforeAllocating) {
  const auto dir = test::scratchDir("gltf_counts");
  const std::string json = TriangleFile{}.json();
  expectInputError(
      write(dir / "indices.gltf", replaced(json, "\"count\": 3, \"type\": \"SCALAR\"",
                                           "\"count\": 4611686018427387904, \"type\": \"SCALAR\"")),
      "triangles");
  expectInputError(
      write(dir / "positions.gltf", replaced(json, "\"count\": 3, \"type\": \"VEC3\"",
                                             "\"count\": 4611686018427387904, \"type\": \"VEC3\"")),
      "vertices");
  // Within the limits but past the buffer, and an offset that wraps a 64-bit end-of-data sum
  // around to look in bounds: both refused by the bounds check.
  expectInputError(write(dir / "overrun.gltf", replaced(json, "\"count\": 3, \"type\": \"VEC3\"",
                                                        "\"count\": 11999999, \"type\": \"VEC3\"")),
                   "inside buffer");
  expectInputError(write(dir / "offset.gltf",
                         replaced(json, "\"byteOffset\": 0,", "\"byteOffset\": 18446744073709551600,")),
                   "inside buffer");
}

// A 10-million-triangle relic is refused with the limit in the message, from the accessor's
// count alone (this file holds one triangle's bytes).
TEST(GltfIo, TenMillionTriangleRelicIsRefusedWithTheLimit) {
  const auto dir = test::scratchDir("gltf_10m");
  const std::string json = replaced(TriangleFile{}.json(), "\"count\": 3, \"type\": \"SCALAR\"",
                                    "\"count\": 30000000, \"type\": \"SCALAR\"");
  expectInputError(write(dir / "ten_million.gltf", json),
                   "at most " + std::to_string(kMaxGltfTriangles) + " triangles");
}

// Nodes shared by two parents at each of 40 levels stand for 2^40 instances of one triangle.
TEST(GltfIo, SharedNodesCannotMultiplyTheScene) {
  const auto dir = test::scratchDir("gltf_shared_nodes");
  TriangleFile f;
  f.node = R"({"children": [1, 1]})";
  for (int level = 1; level < 40; ++level)
    f.extra_nodes +=
        ", {\"children\": [" + std::to_string(level + 1) + ", " + std::to_string(level + 1) + "]}";
  f.extra_nodes += R"(, {"mesh": 0})";
  expectInputError(write(dir / "bomb.gltf", f.json()), "node instances");
}

// A texture's size is read from its header: one wider than the limit is refused before decoding.
TEST(GltfIo, OversizedTextureIsRefused) {
  Model m;
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.triangles = {{0, 1, 2}};
  m.meshes.push_back(mesh);
  Material mat;
  mat.base_colour_texture.index = 0;
  m.materials.push_back(mat);
  m.textures.emplace_back(cv::Mat(1, kMaxGltfTextureSide + 1, CV_8UC3, cv::Scalar(1, 2, 3)));
  try {
    loadGlbFromMemory(encodeGlb(m), "wide.glb");
    ADD_FAILURE() << "a " << kMaxGltfTextureSide + 1 << " pixel wide texture loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at most " + std::to_string(kMaxGltfTextureSide)), std::string::npos)
        << e.what();
  }
  m.textures[0] = Texture(cv::Mat(1, kMaxGltfTextureSide, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_EQ(loadGlbFromMemory(encodeGlb(m), "limit.glb").textures.size(), 1u);
}

struct RealModel {
  const char* file;
  std::size_t triangles;
};

// Every real model in ../shared/data/models loads, with the README's triangle count, finite
// unit normals and sane materials.
TEST(GltfIo, LoadsTheRealModels) {
  HOLO_REQUIRE_SHARED_DATA("models/greek_vase_mr.glb");
  const RealModel models[] = {{"models/greek_vase_mr.glb", 572},
                              {"models/teapots_mr.glb", 2976},
                              {"models/bunny_nodraco.glb", 5648},
                              {"models/glmark2_bunny_mr.glb", 69666}};
  for (const auto& r : models) {
    SCOPED_TRACE(r.file);
    const Model m = loadGltf(test::sharedData(r.file));
    EXPECT_EQ(m.triangleCount(), r.triangles);
    EXPECT_FALSE(m.bounds().empty());
    for (const auto& mesh : m.meshes) {
      ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
      for (const auto& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f);
      for (const auto& t : mesh.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), mesh.positions.size());
      ASSERT_GE(mesh.material, 0);
      ASSERT_LT(mesh.material, static_cast<int>(m.materials.size()));
    }
    for (const auto& mat : m.materials) {
      EXPECT_GE(mat.roughness, 0.0f);
      EXPECT_LE(mat.roughness, 1.0f);
    }
  }
  // The Greek vase is textured: its base colour texture is decoded.
  const Model vase = loadGltf(test::sharedData("models/greek_vase_mr.glb"));
  bool textured = false;
  for (const auto& mat : vase.materials)
    if (mat.base_colour_texture.used())
      textured = !vase.textures[static_cast<std::size_t>(mat.base_colour_texture.index)].empty();
  EXPECT_TRUE(textured);
}

}  // namespace
// External buffers and images are read only from inside the glTF's folder: an absolute URI, one
// climbing out with '..' (percent-encoded too) or through a symlink leading out is an InputError
// naming the file and the field, whatever lies outside. A GLB from memory reads nothing external.
TEST(GltfIo, ExternalFilesCannotLeaveTheGltfsFolder) {
  TriangleFile f;
  const std::string data = bytesOf(f.positions) + bytesOf(f.indices);
  const auto outside = test::scratchDir("gltf_outside");
  write(outside / "tri.bin", data);
  write(outside / "tex.png", "not read");
  const auto dir = test::scratchDir("gltf_confined");
  fs::create_directories(dir / "parts");
  write(dir / "parts" / "tri.bin", data);
  fs::create_directory_symlink(outside, dir / "link_out");
  fs::create_symlink(outside / "tri.bin", dir / "escape.bin");
  fs::create_symlink(dir / "parts" / "tri.bin", dir / "alias.bin");
  for (const std::string uri : {"parts/tri.bin", "./parts/../parts/tri.bin", "alias.bin"}) {
    f.buffer_uri = uri;
    EXPECT_EQ(loadGltf(write(dir / "in.gltf", f.json())).triangleCount(), 1u) << uri;
  }
  const auto expectRefused = [](const fs::path& path, const std::string& field, const std::string& uri) {
    try {
      loadGltf(path);
      ADD_FAILURE() << "read " << uri;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path.string()) << uri;
      EXPECT_EQ(e.field(), field) << uri;
      EXPECT_NE(std::string(e.what()).find("inside the glTF's folder"), std::string::npos) << e.what();
    }
  };
  for (const std::string& uri :
       {(outside / "tri.bin").string(), std::string("../gltf_outside/tri.bin"),
        std::string("%2e%2e/gltf_outside/tri.bin"), std::string("parts/../../gltf_outside/tri.bin"),
        std::string("link_out/tri.bin"), std::string("escape.bin")}) {
    f.buffer_uri = uri;
    expectRefused(write(dir / "out.gltf", f.json()), "buffers[0].uri", uri);
  }
  f.buffer_uri = "parts/tri.bin";
  expectRefused(
      write(dir / "image.gltf", replaced(f.json(), R"("buffers": [)",
                                         R"("images": [{"uri": "../gltf_outside/tex.png"}], "buffers": [)")),
      "images[0].uri", "../gltf_outside/tex.png");

  // A GLB in memory has no folder: its JSON naming an external buffer is refused.
  std::string json = f.json();
  json.resize((json.size() + 3) / 4 * 4, ' ');
  std::vector<std::uint8_t> glb;
  const auto put = [&glb](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  put(0x46546C67);  // "glTF"
  put(2);
  put(static_cast<std::uint32_t>(20 + json.size()));
  put(static_cast<std::uint32_t>(json.size()));
  put(0x4E4F534A);  // "JSON"
  glb.insert(glb.end(), json.begin(), json.end());
  try {
    loadGlbFromMemory(glb, "memory.glb");
    ADD_FAILURE() << "a GLB from memory read an external buffer";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "memory.glb");
    EXPECT_EQ(e.field(), "buffers[0].uri");
    EXPECT_NE(std::string(e.what()).find("only embedded data"), std::string::npos) << e.what();
  }
}

}  // namespace holo
