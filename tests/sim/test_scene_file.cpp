#include <gtest/gtest.h>
#include <fstream>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/relics/relics.hpp"
#include "holo/sim/museum.hpp"
#include "shared_data.hpp"

namespace holo::sim {
namespace {

std::filesystem::path write(const std::filesystem::path& dir, const std::string& name,
                            const std::string& text) {
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

TEST(SceneFile, ReadsEveryField) {
  const auto dir = test::scratchDir("sim_scene_ok");
  saveGltf(dir / "pot.glb", relics::makeRelic("kettle"));
  const auto path = write(dir, "hall.yaml", R"(base: museum
hall: atrium
relic: pot.glb
relic_roughness: 0.25
visitors: 5
seed: 42
camera: {width: 320, height: 180, hfov_deg: 90, max_range: 12, fps: 15}
noise: {sigma_0: 0.002, k_z2: 0.004, enabled: true}
panorama_position: [0, 0.5, 0]
)");
  const SceneDescription d = loadScene(path.string());
  EXPECT_EQ(d.name, "hall");
  EXPECT_EQ(d.source, path.string());
  EXPECT_EQ(d.hall, "atrium");
  EXPECT_EQ(d.relic, (dir / "pot.glb").string());
  EXPECT_FLOAT_EQ(d.relic_roughness, 0.25f);
  EXPECT_EQ(d.visitors, 5);
  EXPECT_EQ(d.seed, 42u);
  EXPECT_EQ(d.camera.width, 320);
  EXPECT_FLOAT_EQ(d.camera.hfov_deg, 90.0f);
  EXPECT_FLOAT_EQ(d.camera.vfov_deg, 70.0f);  // kept from the default
  EXPECT_FLOAT_EQ(d.noise.k_z2, 0.004f);
  EXPECT_FLOAT_EQ(d.panorama_position.y, 0.5f);
  SceneDescription tiny = d;
  tiny.camera.width = 32;
  tiny.camera.height = 18;
  const Museum m(tiny);
  EXPECT_EQ(m.visitorHeads(0).size(), 5u);
  for (const auto& mat : m.relic().materials) EXPECT_FLOAT_EQ(mat.roughness, 0.25f);
}

// Each bad field gives an InputError naming the file and that field.
TEST(SceneFile, BadFieldsNameTheField) {
  const auto dir = test::scratchDir("sim_scene_bad");
  const std::pair<std::string, std::string> cases[] = {
      {"hall: cellar\n", "hall"},
      {"relic: missing.glb\n", "relic"},
      {"visitors: many\n", "visitors"},
      {"visitors: -2\n", "visitors"},
      {"seed: 1.5\n", "seed"},
      {"colour: red\n", "colour"},
      {"camera: {width: 2}\n", "camera.width"},
      {"camera: {hfov_deg: 400}\n", "camera.hfov_deg"},
      {"camera: {zoom: 2}\n", "camera.zoom"},
      {"noise: {k_z2: -1}\n", "noise.k_z2"},
      {"noise: {enabled: maybe}\n", "noise.enabled"},
      {"panorama_position: [0, 1]\n", "panorama_position"},
      {"base: cathedral\n", "base"},
      {"hall: [unclosed\n", ""},
  };
  int i = 0;
  for (const auto& [text, field] : cases) {
    SCOPED_TRACE(text);
    const auto path = write(dir, "bad" + std::to_string(i++) + ".yaml", text);
    try {
      loadScene(path.string());
      ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path.string());
      if (!field.empty()) {
        EXPECT_EQ(e.field().substr(0, e.field().find(' ')), field) << e.what();
      }
    }
  }
  EXPECT_THROW(loadScene((dir / "absent.yaml").string()), InputError);
}

}  // namespace
}  // namespace holo::sim

namespace holo::sim {
namespace {

TEST(SceneFile, TheExampleFileLoads) {
  const SceneDescription d = loadScene(std::string(HOLO_SOURCE_DIR) + "/sim/scenes/example.yaml");
  EXPECT_EQ(d.hall, "atrium");
  EXPECT_EQ(d.relic, "kettle");
  EXPECT_EQ(d.visitors, 4);
  EXPECT_EQ(d.visitor_model, VisitorModel::bodies);
  EXPECT_EQ(d.seed, 7u);
  EXPECT_EQ(d.noise.profile, SensorProfile::structured_light);
  EXPECT_FLOAT_EQ(d.noise.metal_dropout, 0.9f);
  EXPECT_FLOAT_EQ(d.noise.highlight_deg, 12.0f);
}

// A real model as the relic: fitted onto the pedestal like the procedural ones.
TEST(SceneFile, RealModelAsRelic) {
  HOLO_REQUIRE_SHARED_DATA("models/teapots_mr.glb");
  SceneDescription d = loadScene("empty");
  d.relic = test::sharedData("models/teapots_mr.glb").string();
  d.camera.width = 32;
  d.camera.height = 18;
  const Museum m(d);
  const Bounds3 b = m.relic().bounds();
  EXPECT_EQ(m.relic().triangleCount(), 2976u);
  EXPECT_NEAR(b.lo.y, 0.0f, 1e-4f);
  EXPECT_LE(b.hi.y, relics::kRelicHeight + 1e-4f);
  EXPECT_LE(std::max(b.extent().x, b.extent().z), relics::kRelicMaxWidth + 1e-4f);
}

}  // namespace
}  // namespace holo::sim
