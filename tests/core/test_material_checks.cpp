// `holopyramid info`'s material warnings: a BLEND material of alpha 0 hides its meshes, and a glass
// thickness far from the walls of its meshes.
#include <gtest/gtest.h>

#include "holo/core/material_checks.hpp"
#include "holo/core/shapes.hpp"

namespace holo {
namespace {

// A 0.2 m cube (walls 0.2 m across, face to opposite face) with one material.
Model cubeWith(const Material& material) {
  Model model;
  model.meshes.push_back(makeBox(vec3(0.1f)));
  model.meshes.back().material = 0;
  model.materials.push_back(material);
  return model;
}

TEST(MaterialChecks, ABlendMaterialOfAlphaZeroIsReportedInvisible) {
  Material m;
  m.name = "veil";
  m.alpha_mode = AlphaMode::Blend;
  m.alpha = 0.0f;
  const std::vector<MaterialWarning> hidden = checkMaterials(cubeWith(m));
  ASSERT_EQ(hidden.size(), 1u);
  EXPECT_NE(hidden[0].message.find("\"veil\""), std::string::npos) << hidden[0].message;
  EXPECT_NE(hidden[0].message.find("invisible"), std::string::npos) << hidden[0].message;
  m.alpha = 0.3f;  // faint, not invisible
  EXPECT_TRUE(checkMaterials(cubeWith(m)).empty());
  m.alpha = 0.0f;
  m.alpha_mode = AlphaMode::Opaque;  // OPAQUE ignores the alpha
  EXPECT_TRUE(checkMaterials(cubeWith(m)).empty());
}

TEST(MaterialChecks, AGlassThicknessFarFromTheWallsIsReported) {
  Material glass;
  glass.name = "glass";
  glass.transmission = 1.0f;
  glass.thickness = 0.2f;  // the cube's own size: nothing to say
  EXPECT_TRUE(checkMaterials(cubeWith(glass)).empty());
  for (const float far : {0.005f, 5.0f}) {
    glass.thickness = far;
    const std::vector<MaterialWarning> w = checkMaterials(cubeWith(glass));
    ASSERT_EQ(w.size(), 1u) << far;
    EXPECT_NE(w[0].message.find("thickness"), std::string::npos) << w[0].message;
    EXPECT_NE(w[0].message.find("0.2"), std::string::npos) << w[0].message;  // the wall it measured
  }
  glass.thickness = 0.0f;  // thin-walled: no volume to compare
  EXPECT_TRUE(checkMaterials(cubeWith(glass)).empty());
}

}  // namespace
}  // namespace holo
