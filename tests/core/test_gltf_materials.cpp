// Materials as glTF 2.0 and its material extensions state them, written as small documents with
// an external buffer and PNG next to them, and the Khronos sample relics in ../shared/data.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/stats.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

namespace fs = std::filesystem;

// The unit square facing +Z with TEXCOORD_0 = (x, y) and TEXCOORD_1 = (y, x), one 2x2 PNG
// texture behind `textures`, and the material, samplers and extension lists given.
struct QuadFile {
  std::string material = R"({"name": "plain"})";
  std::string samplers = R"([{}])";
  std::string textures = R"([{"source": 0, "sampler": 0}])";
  std::string extensions;  // e.g. , "extensionsUsed": [...]

  fs::path write(const fs::path& dir, const std::string& name) const {
    const std::vector<float> positions{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> uv0{0, 0, 1, 0, 1, 1, 0, 1};
    const std::vector<float> uv1{0, 0, 0, 1, 1, 1, 1, 0};
    const std::vector<std::uint16_t> indices{0, 1, 2, 0, 2, 3};
    std::ofstream bin(dir / "quad.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(positions.data()), 48);
    bin.write(reinterpret_cast<const char*>(uv0.data()), 32);
    bin.write(reinterpret_cast<const char*>(uv1.data()), 32);
    bin.write(reinterpret_cast<const char*>(indices.data()), 12);
    bin.close();
    cv::imwrite((dir / "tex.png").string(), cv::Mat(2, 2, CV_8UC3, cv::Scalar(10, 20, 30)));
    const fs::path path = dir / name;
    std::ofstream(path) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2},
                              "indices": 3, "material": 0}]}],
  "materials": [)" + material + R"(],
  "images": [{"uri": "tex.png"}], "samplers": )" +
                               samplers + R"(, "textures": )" + textures + R"(,
  "buffers": [{"uri": "quad.bin", "byteLength": 124}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 80, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 112, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}])" +
                               extensions + "}";
    return path;
  }
};

const char* kEveryProperty = R"({"name": "glaze",
  "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 0.5], "metallicFactor": 0.25,
    "roughnessFactor": 0.75,
    "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
        {"offset": [0.5, 0.25], "rotation": 1.5707964, "scale": [2, 3], "texCoord": 1}}},
    "metallicRoughnessTexture": {"index": 0}},
  "normalTexture": {"index": 0, "scale": 0.5},
  "occlusionTexture": {"index": 0, "texCoord": 1, "strength": 0.7},
  "emissiveTexture": {"index": 0}, "emissiveFactor": [1.0, 0.5, 0.25],
  "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true,
  "extensions": {
    "KHR_materials_emissive_strength": {"emissiveStrength": 4},
    "KHR_materials_specular": {"specularFactor": 0.6, "specularColorFactor": [1.5, 1, 0.5],
        "specularTexture": {"index": 0}, "specularColorTexture": {"index": 0}},
    "KHR_materials_clearcoat": {"clearcoatFactor": 0.9, "clearcoatRoughnessFactor": 0.15,
        "clearcoatTexture": {"index": 0}, "clearcoatRoughnessTexture": {"index": 0},
        "clearcoatNormalTexture": {"index": 0, "scale": 0.8}},
    "KHR_materials_transmission": {"transmissionFactor": 0.95, "transmissionTexture": {"index": 0}},
    "KHR_materials_volume": {"thicknessFactor": 0.02, "thicknessTexture": {"index": 0},
        "attenuationColor": [0.8, 0.9, 1.0], "attenuationDistance": 0.05},
    "KHR_materials_ior": {"ior": 2.42}}})";

const char* kEveryExtension = R"(, "extensionsUsed": ["KHR_texture_transform",
    "KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_clearcoat",
    "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"])";

// Loading must fail with an InputError naming the file whose message contains every needle.
void expectInputError(const fs::path& path, std::initializer_list<std::string> needles) {
  try {
    loadGltf(path);
    ADD_FAILURE() << "expected InputError for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    for (const auto& needle : needles)
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what() << " lacks " << needle;
  }
}

TEST(GltfMaterials, ReadsEveryPropertyAndExtension) {
  const auto dir = test::scratchDir("gltf_materials_all");
  QuadFile f;
  f.material = kEveryProperty;
  f.samplers = R"([{"wrapS": 33071, "wrapT": 33648, "magFilter": 9728, "minFilter": 9985}])";
  f.extensions = kEveryExtension;
  const fs::path path = f.write(dir, "all.gltf");
  const Model model = loadGltf(path);
  ASSERT_EQ(model.materials.size(), 1u);
  const Material& m = model.materials[0];
  EXPECT_FLOAT_EQ(m.alpha, 0.5f);
  EXPECT_FLOAT_EQ(m.base_colour.b, 0.6f);
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.75f);
  EXPECT_FLOAT_EQ(m.emission.r, 4.0f);
  EXPECT_FLOAT_EQ(m.emission.b, 1.0f);
  EXPECT_EQ(m.alpha_mode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
  EXPECT_FLOAT_EQ(m.occlusion_strength, 0.7f);
  EXPECT_EQ(m.occlusion_texture.tex_coord, 1);
  EXPECT_FLOAT_EQ(m.specular, 0.6f);
  EXPECT_FLOAT_EQ(m.specular_colour.r, 1.5f);  // specular colour may exceed 1
  EXPECT_FLOAT_EQ(m.clearcoat, 0.9f);
  EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.15f);
  EXPECT_FLOAT_EQ(m.clearcoat_normal_scale, 0.8f);
  EXPECT_FLOAT_EQ(m.transmission, 0.95f);
  EXPECT_TRUE(m.transmissive());
  EXPECT_FLOAT_EQ(m.thickness, 0.02f);
  EXPECT_FLOAT_EQ(m.attenuation_colour.g, 0.9f);
  EXPECT_FLOAT_EQ(m.attenuation_distance, 0.05f);
  EXPECT_FLOAT_EQ(m.ior, 2.42f);
  // All twelve slots use the one glTF texture; it is built once as sRGB colour (the colour slots,
  // read first) and once as linear data (the other nine), each with its sampler and mips.
  for (const TextureRef* slot : {&m.base_colour_texture, &m.emissive_texture, &m.specular_colour_texture})
    EXPECT_EQ(slot->index, 0);
  for (const TextureRef* slot : {&m.metallic_roughness_texture, &m.normal_texture, &m.occlusion_texture,
                                 &m.specular_texture, &m.clearcoat_texture, &m.clearcoat_roughness_texture,
                                 &m.clearcoat_normal_texture, &m.transmission_texture, &m.thickness_texture})
    EXPECT_EQ(slot->index, 1);
  ASSERT_EQ(model.textures.size(), 2u);
  EXPECT_EQ(model.textures[0].encoding, TextureEncoding::Srgb);
  EXPECT_EQ(model.textures[1].encoding, TextureEncoding::Linear);
  EXPECT_EQ(cv::norm(model.textures[0].image(), model.textures[1].image(), cv::NORM_INF), 0.0);
  const Texture& t = model.textures[0];
  EXPECT_EQ(t.levels.size(), 2u);  // 2x2, 1x1
  EXPECT_EQ(t.image().at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(t.sampler.wrap_u, TextureWrap::ClampToEdge);
  EXPECT_EQ(t.sampler.wrap_v, TextureWrap::MirroredRepeat);
  EXPECT_FALSE(t.sampler.magnify_linear);
  EXPECT_TRUE(t.sampler.minify_linear);
  EXPECT_TRUE(t.sampler.use_mips);
  EXPECT_FALSE(t.sampler.blend_mips);
  // KHR_texture_transform: its texCoord overrides the slot's; uv' = offset + R(rotation) (scale uv).
  const TextureRef& base = m.base_colour_texture;
  EXPECT_EQ(base.tex_coord, 1);
  const vec2 moved = base.transform({1.0f, 0.0f});  // scaled (2, 0), rotated a quarter turn: (0, -2)
  EXPECT_NEAR(moved.x, 0.5f, 1e-6f);
  EXPECT_NEAR(moved.y, -1.75f, 1e-6f);
  // Geometry: TEXCOORD_1 read, tangents generated (there is a normal map and no TANGENT).
  const TriangleMesh& mesh = model.meshes.at(0);
  ASSERT_EQ(mesh.uvs1.size(), 4u);
  EXPECT_EQ(mesh.uvs1[1], vec2(0, 1));
  ASSERT_EQ(mesh.tangents.size(), 4u);
  for (const vec4& tangent : mesh.tangents) EXPECT_LT(glm::length(tangent - vec4(1, 0, 0, 1)), 1e-6f);
  // Both renderers read all twelve slots: `holopyramid info` lists each as rendered.
  const GltfInventory inventory = inspectGltf(path);
  EXPECT_EQ(inventory.texture_slots.size(), 12u);
  for (const GltfFeature& slot : inventory.texture_slots)
    EXPECT_EQ(slot.support, GltfSupport::Rendered) << slot.name;
}

// Written and read back, every property survives (saveGltf writes the same extensions).
TEST(GltfMaterials, RoundTripKeepsEveryProperty) {
  const auto dir = test::scratchDir("gltf_materials_roundtrip");
  QuadFile f;
  f.material = kEveryProperty;
  f.extensions = kEveryExtension;
  const Model model = loadGltf(f.write(dir, "all.gltf"));
  saveGltf(dir / "again.glb", model);
  const Material& a = model.materials[0];
  const Model back = loadGltf(dir / "again.glb");
  const Material& b = back.materials.at(0);
  EXPECT_FLOAT_EQ(b.alpha, a.alpha);
  EXPECT_EQ(b.alpha_mode, a.alpha_mode);
  EXPECT_EQ(b.double_sided, a.double_sided);
  EXPECT_FLOAT_EQ(b.emission.r, a.emission.r);
  EXPECT_FLOAT_EQ(b.normal_scale, a.normal_scale);
  EXPECT_FLOAT_EQ(b.occlusion_strength, a.occlusion_strength);
  EXPECT_FLOAT_EQ(b.specular_colour.r, a.specular_colour.r);
  EXPECT_FLOAT_EQ(b.clearcoat_normal_scale, a.clearcoat_normal_scale);
  EXPECT_FLOAT_EQ(b.transmission, a.transmission);
  EXPECT_FLOAT_EQ(b.attenuation_distance, a.attenuation_distance);
  EXPECT_FLOAT_EQ(b.ior, a.ior);
  EXPECT_EQ(b.base_colour_texture.tex_coord, 1);
  EXPECT_FLOAT_EQ(b.base_colour_texture.rotation, a.base_colour_texture.rotation);
  EXPECT_EQ(b.base_colour_texture.offset, a.base_colour_texture.offset);
  ASSERT_TRUE(b.clearcoat_normal_texture.used() && b.base_colour_texture.used());
  EXPECT_EQ(back.textures.at(std::size_t(b.clearcoat_normal_texture.index)).encoding,
            TextureEncoding::Linear);
  EXPECT_EQ(back.textures.at(std::size_t(b.base_colour_texture.index)).encoding, TextureEncoding::Srgb);
  EXPECT_EQ(back.meshes.at(0).uvs1, model.meshes.at(0).uvs1);
  EXPECT_EQ(back.meshes.at(0).tangents, model.meshes.at(0).tangents);
}

TEST(GltfMaterials, UnsupportedRequiredExtensionIsAnError) {
  const auto dir = test::scratchDir("gltf_materials_required");
  QuadFile f;
  f.extensions =
      R"(, "extensionsUsed": ["KHR_materials_sheen"], "extensionsRequired": ["KHR_materials_sheen"])";
  expectInputError(f.write(dir, "sheen.gltf"), {"extensionsRequired", "KHR_materials_sheen"});
}

TEST(GltfMaterials, UnsupportedOptionalExtensionIsACountedWarning) {
  const auto dir = test::scratchDir("gltf_materials_optional");
  QuadFile f;
  f.extensions =
      R"(, "extensionsUsed": ["KHR_materials_sheen", "KHR_materials_iridescence", "KHR_materials_ior"])";
  const auto& ignored = stats::counter("glTF/Optional extensions ignored");
  const auto before = ignored.load();
  const fs::path path = f.write(dir, "sheen.gltf");
  EXPECT_EQ(loadGltf(path).materials.size(), 1u);
  EXPECT_EQ(ignored.load() - before, 2);  // sheen and iridescence; the IOR extension is read
  const GltfInventory inventory = inspectGltf(path);
  ASSERT_EQ(inventory.extensions.size(), 3u);
  EXPECT_EQ(inventory.extensions[0].support, GltfSupport::Ignored);
  EXPECT_EQ(inventory.extensions[2].support, GltfSupport::Rendered);
}

// Each bad factor is named with its material: a technician can find it in the exporter.
TEST(GltfMaterials, NegativeAndMalformedFactorsNameTheMaterialAndField) {
  const auto dir = test::scratchDir("gltf_materials_bad");
  struct Case {
    const char* material;
    const char* field;
  };
  const Case cases[] = {
      {R"({"name": "vase", "pbrMetallicRoughness": {"metallicFactor": -0.5}})", "metallicFactor"},
      {R"({"name": "vase", "pbrMetallicRoughness": {"baseColorFactor": [1, -1, 1, 1]}})",
       "baseColorFactor[1]"},
      {R"({"name": "vase", "emissiveFactor": [0, 0, -2]})", "emissiveFactor[2]"},
      {R"({"name": "vase", "occlusionTexture": {"index": 0, "strength": -1}})", "strength"},
      {R"({"name": "vase", "extensions": {"KHR_materials_transmission": {"transmissionFactor": -0.1}}})",
       "transmissionFactor"},
      {R"({"name": "vase", "extensions": {"KHR_materials_volume": {"thicknessFactor": -2}}})",
       "thicknessFactor"},
      {R"({"name": "vase", "extensions": {"KHR_materials_volume": {"attenuationDistance": 0}}})",
       "attenuationDistance"},
      {R"({"name": "vase", "extensions": {"KHR_materials_volume": {"attenuationColor": [1, 1]}}})",
       "attenuationColor"},
      {R"({"name": "vase", "extensions": {"KHR_materials_ior": {"ior": 0.5}}})", "ior"},
      {R"({"name": "vase", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": "thick"}}})",
       "clearcoatFactor"},
      {R"({"name": "vase", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": -3}}})",
       "emissiveStrength"},
      {R"({"name": "vase", "normalTexture": {"index": 0, "texCoord": 2}})", "texCoord"},
      {R"({"name": "vase", "emissiveTexture": {"index": 5}})", "textures"},
      {R"({"name": "vase", "alphaMode": "CUTOUT"})", "alphaMode"},
  };
  int i = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.material);
    QuadFile f;
    f.material = c.material;
    const std::string name = "bad" + std::to_string(i++) + ".gltf";
    // An index out of range names the file's textures array, not the material.
    if (std::string(c.field) == "textures")
      expectInputError(f.write(dir, name), {c.field});
    else
      expectInputError(f.write(dir, name), {"vase", c.field});
  }
}

// JSON has no NaN or infinity: such a factor stops the parser, and the error names the token.
TEST(GltfMaterials, NonFiniteFactorsAreRejectedByTheParser) {
  const auto dir = test::scratchDir("gltf_materials_nonfinite");
  QuadFile f;
  f.material = R"({"name": "vase", "pbrMetallicRoughness": {"roughnessFactor": 1e999}})";
  expectInputError(f.write(dir, "inf.gltf"), {"1e999"});
  f.material = R"({"name": "vase", "pbrMetallicRoughness": {"roughnessFactor": NaN}})";
  expectInputError(f.write(dir, "nan.gltf"), {"glTF"});
}

// The stability cases' extremes are legal and load unchanged: a renderer must handle them.
TEST(GltfMaterials, ExtremeButLegalValuesLoadUnchanged) {
  const auto dir = test::scratchDir("gltf_materials_extreme");
  QuadFile f;
  f.material = R"({"name": "edge", "extensions": {"KHR_materials_ior": {"ior": 1.0},
      "KHR_materials_transmission": {"transmissionFactor": 1},
      "KHR_materials_volume": {"thicknessFactor": 0, "attenuationDistance": 1e-6}}})";
  const Model m = loadGltf(f.write(dir, "edge.gltf"));
  EXPECT_FLOAT_EQ(m.materials[0].ior, 1.0f);
  EXPECT_FLOAT_EQ(m.materials[0].thickness, 0.0f);
  EXPECT_FLOAT_EQ(m.materials[0].attenuation_distance, 1e-6f);
  // Factors above their bound of 1 are clamped and counted.
  f.material = R"({"name": "bright", "pbrMetallicRoughness": {"metallicFactor": 1.5}})";
  const auto& clamped = stats::counter("glTF/Material factors clamped to 1");
  const auto before = clamped.load();
  EXPECT_FLOAT_EQ(loadGltf(f.write(dir, "bright.gltf")).materials[0].metallic, 1.0f);
  EXPECT_EQ(clamped.load() - before, 1);
}

struct KhronosModel {
  const char* file;
  const char* extension;  // one extension it must report
};

// The four Khronos relics load with every material they declare, and the inventory lists each
// extension and texture slot they use with its state.
TEST(GltfMaterials, KhronosRelicsLoadEveryMaterial) {
  HOLO_REQUIRE_SHARED_DATA("models/khronos_attenuation_test.glb");
  HOLO_REQUIRE_SHARED_DATA("models/khronos_clearcoat_wicker.glb");
  HOLO_REQUIRE_SHARED_DATA("models/khronos_glass_hurricane_candle_holder.glb");
  HOLO_REQUIRE_SHARED_DATA("models/khronos_transmission_roughness_test.glb");
  const auto& ignored = stats::counter("glTF/Optional extensions ignored");
  const auto before = ignored.load();
  {
    const GltfInventory inv =
        inspectGltf(test::sharedData("models/khronos_glass_hurricane_candle_holder.glb"));
    ASSERT_EQ(inv.model.materials.size(), 2u);
    const Material& glass = inv.model.materials[1];
    EXPECT_FLOAT_EQ(glass.transmission, 1.0f);
    EXPECT_FLOAT_EQ(glass.thickness, 0.1f);
    EXPECT_FLOAT_EQ(glass.attenuation_distance, 0.001f);
    EXPECT_FLOAT_EQ(glass.attenuation_colour.g, 0.95f);
    EXPECT_TRUE(glass.thickness_texture.used());
    EXPECT_TRUE(glass.occlusion_texture.used());
    EXPECT_FALSE(inv.model.materials[0].transmissive());
    ASSERT_EQ(inv.extensions.size(), 2u);
    for (const auto& e : inv.extensions) EXPECT_EQ(e.support, GltfSupport::Rendered) << e.name;
    bool thickness_slot = false, base_rendered = false;
    for (const auto& s : inv.texture_slots) {
      thickness_slot |= s.name == "thicknessTexture" && s.materials == 1;
      base_rendered |= s.name == "baseColorTexture" && s.support == GltfSupport::Rendered && s.materials == 2;
    }
    EXPECT_TRUE(thickness_slot);
    EXPECT_TRUE(base_rendered);
  }
  {
    const Model wicker = loadGltf(test::sharedData("models/khronos_clearcoat_wicker.glb"));
    ASSERT_EQ(wicker.materials.size(), 1u);
    const Material& m = wicker.materials[0];
    EXPECT_FLOAT_EQ(m.clearcoat, 1.0f);
    EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.1f);
    EXPECT_TRUE(m.clearcoat_normal_texture.used());
    EXPECT_TRUE(m.normal_texture.used());
    EXPECT_NE(m.clearcoat_normal_texture.index, m.normal_texture.index);
    // Occlusion and metal-rough share one texture, decoded once.
    EXPECT_EQ(m.occlusion_texture.index, m.metallic_roughness_texture.index);
    EXPECT_EQ(wicker.textures.size(), 4u);
  }
  {
    const Model grid = loadGltf(test::sharedData("models/khronos_transmission_roughness_test.glb"));
    float lowest = 10, highest = 0;
    int transmissive = 0;
    for (const auto& m : grid.materials) {
      if (!m.transmissive()) continue;
      ++transmissive;
      lowest = std::min(lowest, m.ior);
      highest = std::max(highest, m.ior);
    }
    EXPECT_GT(transmissive, 0);
    EXPECT_FLOAT_EQ(lowest, 1.0f);
    EXPECT_FLOAT_EQ(highest, 2.42f);
  }
  {
    const Model blocks = loadGltf(test::sharedData("models/khronos_attenuation_test.glb"));
    int absorbing = 0;
    for (const auto& m : blocks.materials)
      if (m.transmissive() && std::isfinite(m.attenuation_distance) && m.thickness > 0.0f) ++absorbing;
    EXPECT_GT(absorbing, 0);
  }
  EXPECT_EQ(ignored.load(), before);  // nothing in them is skipped
}

}  // namespace
}  // namespace holo
