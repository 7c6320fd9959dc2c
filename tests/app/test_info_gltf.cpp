// `holopyramid info` on glTF relics: every extension and texture slot with its state, and an
// unreadable required extension refused with exit status 2 naming it.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "run_holopyramid.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(InfoGltf, ListsEveryExtensionAndTextureSlotWithItsState) {
  HOLO_REQUIRE_SHARED_DATA("models/khronos_glass_hurricane_candle_holder.glb");
  const auto dir = test::scratchDir("app_info_gltf");
  const auto model = test::sharedData("models/khronos_glass_hurricane_candle_holder.glb");
  ASSERT_EQ(test::runHolopyramid("info " + model.string(), dir / "out.txt"), 0) << readText(dir / "out.txt");
  const std::string out = readText(dir / "out.txt");
  for (const char* line :
       {"KHR_materials_transmission: rendered (1 material)", "KHR_materials_volume: rendered (1 material)",
        "baseColorTexture: rendered (2 materials)", "occlusionTexture: rendered (2 materials)",
        "thicknessTexture: rendered (1 material)", "material warnings: 1",
        "material 1 (\"GlassHurricaneCandleHolder-glass\"): KHR_materials_volume thickness 0.1 is far from "
        "its "
        "meshes' walls"})
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
}

TEST(InfoGltf, RequiredExtensionThisBuildCannotReadIsRefused) {
  const auto dir = test::scratchDir("app_info_gltf_required");
  std::ofstream(dir / "sheen.gltf") << R"({"asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_materials_sheen"], "extensionsRequired": ["KHR_materials_sheen"]})";
  EXPECT_EQ(test::runHolopyramid("info " + (dir / "sheen.gltf").string(), dir / "out.txt"), 2);
  const std::string out = readText(dir / "out.txt");
  EXPECT_NE(out.find("KHR_materials_sheen"), std::string::npos) << out;
  EXPECT_NE(out.find("sheen.gltf"), std::string::npos) << out;
}

}  // namespace
}  // namespace holo
