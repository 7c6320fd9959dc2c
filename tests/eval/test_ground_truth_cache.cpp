// The ground-truth cache's key covers what changes the truth (geometry, materials, textures,
// panorama, visitors, view, samples, seed, the path tracer's version) and nothing stale is read
// back after such a change.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "holo/eval/ground_truth_cache.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "shared_data.hpp"

namespace holo::eval {
namespace {

// A scene built in memory: the sphere relic, a one-triangle "hall", a small uniform panorama.
ReflectionScene smallScene() {
  ReflectionScene s;
  s.relic = relics::makeRelic("sphere");
  relics::fitOnPedestal(s.relic);
  Model hall;
  Material wall_material;
  wall_material.emission = vec3(0.5f);
  hall.materials.push_back(wall_material);
  TriangleMesh wall;
  wall.positions = {{-2, 0, -2}, {2, 0, -2}, {0, 2, -2}};
  wall.triangles = {{0, 1, 2}};
  hall.meshes.push_back(wall);
  s.static_emitters.push_back(hall);
  s.panorama = cv::Mat(8, 16, CV_32FC3, cv::Scalar(0.2, 0.3, 0.4));
  return s;
}

CameraModel smallView(const ReflectionScene& scene, int size = 8) {
  const Bounds3 b = scene.relic.bounds();
  const vec3 eye = reflect::defaultFaceEye(0, b, scene.floor_y);
  return reflect::lookAtCamera(eye, b.center(), reflect::framingFovDeg(eye, b), size, size);
}

TEST(GroundTruthKey, ChangesWithEverythingThatChangesTheTruth) {
  const ReflectionScene base = smallScene();
  const CameraModel view = smallView(base);
  const std::string key = groundTruthKey(base, view, 16, true);
  EXPECT_EQ(groundTruthKey(smallScene(), smallView(base), 16, true), key) << "not deterministic";

  ReflectionScene moved = base;  // the relic's geometry
  moved.relic.meshes.front().positions.front().y += 1e-3f;
  EXPECT_NE(groundTruthKey(moved, view, 16, true), key);

  ReflectionScene rougher = base;  // a material
  rougher.relic.materials.front().roughness += 0.01f;
  EXPECT_NE(groundTruthKey(rougher, view, 16, true), key);

  // Every material field and texture input the path tracer renders.
  const std::vector<std::function<void(Model&)>> material_changes = {
      [](Model& m) { m.materials.front().normal_texture.index = 0; },
      [](Model& m) { m.materials.front().normal_scale = 0.5f; },
      [](Model& m) { m.materials.front().occlusion_strength = 0.5f; },
      [](Model& m) { m.materials.front().emissive_texture.tex_coord = 1; },
      [](Model& m) { m.materials.front().base_colour_texture.rotation = 0.1f; },
      [](Model& m) { m.materials.front().alpha_mode = AlphaMode::Mask; },
      [](Model& m) { m.materials.front().alpha_cutoff = 0.25f; },
      [](Model& m) { m.materials.front().alpha = 0.5f; },
      [](Model& m) { m.materials.front().double_sided = !m.materials.front().double_sided; },
      [](Model& m) { m.materials.front().specular = 0.5f; },
      [](Model& m) { m.meshes.front().uvs1.assign(m.meshes.front().positions.size(), vec2(0.5f)); },
      [](Model& m) { m.meshes.front().tangents.assign(m.meshes.front().positions.size(), vec4(1, 0, 0, 1)); },
  };
  for (std::size_t i = 0; i < material_changes.size(); ++i) {
    ReflectionScene changed = base;
    material_changes[i](changed.relic);
    EXPECT_NE(groundTruthKey(changed, view, 16, true), key) << "material change " << i;
  }
  ReflectionScene sampled = base;  // a texture's sampler
  sampled.relic.textures.emplace_back(cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)));
  ReflectionScene clamped = sampled;
  clamped.relic.textures.back().sampler.wrap_u = TextureWrap::ClampToEdge;
  EXPECT_NE(groundTruthKey(clamped, view, 16, true), groundTruthKey(sampled, view, 16, true));
  // Every factor the path tracer's glass, clearcoat and specular read.
  const std::vector<void (*)(Material&)> glass_edits = {
      [](Material& m) { m.transmission = 1.0f; },         [](Material& m) { m.ior = 2.42f; },
      [](Material& m) { m.thickness = 0.01f; },           [](Material& m) { m.attenuation_colour.x = 0.5f; },
      [](Material& m) { m.attenuation_distance = 1.0f; }, [](Material& m) { m.clearcoat = 1.0f; },
      [](Material& m) { m.clearcoat_roughness = 0.3f; },  [](Material& m) { m.specular = 0.5f; },
      [](Material& m) { m.specular_colour.y = 0.5f; }};
  for (const auto& edit : glass_edits) {
    ReflectionScene glassier = base;
    edit(glassier.relic.materials.front());
    EXPECT_NE(groundTruthKey(glassier, view, 16, true), key);
  }

  ReflectionScene textured = base;  // a texture
  textured.relic.textures.emplace_back(cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_NE(groundTruthKey(textured, view, 16, true), key);

  ReflectionScene hall = base;  // the hall's geometry
  hall.static_emitters.front().meshes.front().positions.back().x += 0.1f;
  EXPECT_NE(groundTruthKey(hall, view, 16, true), key);

  ReflectionScene visitor = base;  // the visitors, only when they are rendered
  visitor.visitors = base.static_emitters.front();
  EXPECT_NE(groundTruthKey(visitor, view, 16, true), key);
  EXPECT_EQ(groundTruthKey(visitor, view, 16, false), groundTruthKey(base, view, 16, false));

  ReflectionScene brighter = base;  // one panorama pixel
  brighter.panorama.at<cv::Vec3f>(3, 5)[1] += 0.01f;
  EXPECT_NE(groundTruthKey(brighter, view, 16, true), key);

  EXPECT_NE(groundTruthKey(base, smallView(base, 9), 16, true), key);                          // the view
  EXPECT_NE(groundTruthKey(base, view, 32, true), key);                                        // the samples
  EXPECT_NE(groundTruthKey(base, view, 16, true, 2), key);                                     // the seed
  EXPECT_NE(groundTruthKey(base, view, 16, true, 1, reference::kPathTracerVersion + 1), key);  // the tracer
}

TEST(CachedGroundTruth, ReadsBackTheSameTruthAndRendersAChangedSceneAgain) {
  const auto dir = test::scratchDir("ground_truth_cache");
  const ReflectionScene base = smallScene();
  const CameraModel view = smallView(base);
  const cv::Mat first = cachedGroundTruth(base, view, 2, true, dir);
  ASSERT_EQ(first.size(), cv::Size(8, 8));
  ASSERT_TRUE(std::filesystem::exists(dir / groundTruthKey(base, view, 2, true)));
  EXPECT_EQ(cv::norm(cachedGroundTruth(base, view, 2, true, dir), first, cv::NORM_L1), 0.0);

  ReflectionScene rougher = base;
  rougher.relic.materials.front().roughness = 0.5f;
  const cv::Mat changed = cachedGroundTruth(rougher, view, 2, true, dir);
  EXPECT_GT(cv::norm(changed, first, cv::NORM_L1), 0.0) << "a stale truth was read back";
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()),
            2);
}

}  // namespace
}  // namespace holo::eval
