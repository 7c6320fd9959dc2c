// The baselines of the tracer evaluation: screen-space ray tracing against the RGBD images
// reprojected to the pyramid origin (ssrt.hpp), and the voxel grid as emitters for path tracing
// the reconstructed scene (voxel_emitters.hpp).
#include "holo/reference/ssrt.hpp"

#include <gtest/gtest.h>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reference/voxel_emitters.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reference {
namespace {

// The scenes, materials and environments the reference renderers read.
using namespace holo::reflect;

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

ForegroundPoint point(const vec3& position, const vec3& radiance) {
  ForegroundPoint p;
  p.position = position;
  p.radiance = radiance;
  return p;
}

TEST(ReprojectedRgbd, KeepsOnlyTheNearestPointPerPixel) {
  ForegroundCloud cloud;
  cloud.points.push_back(point(vec3(0.0f, 0.0f, 2.0f), vec3(0.0f, 1.0f, 0.0f)));  // behind
  cloud.points.push_back(point(vec3(0.0f, 0.0f, 1.0f), vec3(1.0f, 0.0f, 0.0f)));  // nearest
  cloud.points.push_back(point(vec3(0.0f, 0.0f, 1.5f), vec3(0.0f, 0.0f, 1.0f)));
  const ReprojectedRgbd map(cloud, vec3(0.0f), 64);
  EXPECT_EQ(map.width(), 64);
  EXPECT_EQ(map.height(), 32);
  EXPECT_EQ(map.filledPixels(), 1u);
  int pixel = -1;
  EXPECT_FLOAT_EQ(map.depthAlong(vec3(0.0f, 0.0f, 1.0f), &pixel), 1.0f);
  EXPECT_EQ(map.radiance(pixel), vec3(1.0f, 0.0f, 0.0f));
  EXPECT_EQ(map.depthAlong(vec3(0.0f, 0.0f, -1.0f), &pixel), 0.0f);  // a hole: nothing there
}

// A mirror sphere at (0, 0.3, 0) under a grey sky, test::redWall() between it and the viewer.
struct WallScene {
  explicit WallScene(float roughness)
      : scene(holo::test::sphereModel({vec3(0.9f), 1.0f, roughness, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24,
                                      48),
              {}),
        ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16}),
        view(lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 48, 48)),
        wall(holo::test::redWall().cloud) {}
  RenderScene scene;
  PrefilteredIbl ibl;
  CameraModel view;
  ForegroundCloud wall;
};

SsrtSettings coarseMap() {
  SsrtSettings s;
  s.map_width = 256;  // coarser than the wall's point spacing seen from O: no holes
  return s;
}

TEST(Ssrt, MirrorFindsTheWallAndFallsBackToTheSky) {
  const WallScene w(0.0f);
  SsrtStats stats;
  const cv::Mat with = renderSsrt(w.scene, w.ibl, w.wall, w.view, coarseMap(), &stats);
  // The centre reflects straight back at the wall: red times the metal's F0 (0.9).
  const vec3 centre = rgbAt(with, 24, 24);
  EXPECT_NEAR(centre.r, 0.9f * 2.0f, 0.15f);
  EXPECT_NEAR(centre.g, 0.0f, 0.05f);
  EXPECT_EQ(rgbAt(with, 0, 0), vec3(0.0f));  // off the relic: black
  EXPECT_GT(stats.hits, 0u);
  EXPECT_LT(stats.hits, stats.rays);  // rays near the rim pass beside the wall
  const cv::Mat without = renderSsrt(w.scene, w.ibl, ForegroundCloud{}, w.view, coarseMap());
  EXPECT_NEAR(rgbAt(without, 24, 24).g, 0.9f * 0.5f, 0.05f);
}

TEST(Ssrt, FineMapHasHolesWhereThePointsAreSparse) {
  // The paper's SSRT artefact: reprojection to O leaves map pixels empty between the points, and
  // rays through them see the sky. 1 cm point spacing at 0.6 m from O is ~1 degree; a 2048-wide
  // map has 0.18-degree pixels.
  const WallScene w(0.0f);
  SsrtSettings fine = coarseMap();
  fine.map_width = 2048;
  SsrtStats coarse_stats, fine_stats;
  renderSsrt(w.scene, w.ibl, w.wall, w.view, coarseMap(), &coarse_stats);
  renderSsrt(w.scene, w.ibl, w.wall, w.view, fine, &fine_stats);
  EXPECT_LT(double(fine_stats.hits), 0.8 * double(coarse_stats.hits));
}

TEST(Ssrt, StaysFiniteAndNonNegativeForAnyRoughness) {
  for (float roughness : {0.0f, 0.5f, 1.0f}) {
    const WallScene w(roughness);
    SsrtSettings s = coarseMap();
    s.rays = 4;
    const cv::Mat image = renderSsrt(w.scene, w.ibl, w.wall, w.view, s);
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const vec3 c = rgbAt(image, x, y);
        ASSERT_TRUE(isFinite(c)) << roughness;
        ASSERT_GE(glm::min(c.x, glm::min(c.y, c.z)), 0.0f) << roughness;
      }
  }
}

TEST(Ssrt, RejectsBadSettingsNamingTheField) {
  const WallScene w(0.0f);
  SsrtSettings s;
  s.rays = 0;
  try {
    renderSsrt(w.scene, w.ibl, w.wall, w.view, s);
    FAIL() << "rays = 0 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rays"), std::string::npos) << e.what();
  }
  s = SsrtSettings{};
  s.map_width = 101;
  EXPECT_THROW(renderSsrt(w.scene, w.ibl, w.wall, w.view, s), InputError);
}

TEST(VoxelEmitters, OneEmittingCubePerOccupiedVoxel) {
  VoxelGridSettings gs;
  gs.bounds = {vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.5f, 1.0f)};
  gs.voxel_size = 0.1f;
  VoxelGrid grid(gs);
  EXPECT_TRUE(voxelEmitters(grid).meshes.empty());
  ForegroundCloud cloud;
  cloud.points.push_back(point(vec3(0.05f, 0.05f, 0.05f), vec3(1, 0, 0)));
  cloud.points.push_back(point(vec3(0.55f, 0.35f, 0.05f), vec3(0, 1, 0)));
  cloud.points.push_back(point(vec3(0.56f, 0.36f, 0.06f), vec3(0, 1, 0)));  // same voxel
  grid.build(cloud);
  const Model model = voxelEmitters(grid);
  ASSERT_EQ(model.meshes.size(), 2u);
  EXPECT_EQ(model.triangleCount(), 24u);
  for (const TriangleMesh& mesh : model.meshes) {
    const Bounds3 b = mesh.bounds();
    const Bounds3 v = grid.voxelBounds(grid.voxelOf(b.center()));
    EXPECT_NEAR(glm::length(b.lo - v.lo), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(b.hi - v.hi), 0.0f, 1e-5f);
    const vec3 e = model.materials.at(std::size_t(mesh.material)).emission;
    EXPECT_EQ(e, b.center().x < 0.3f ? vec3(1, 0, 0) : vec3(0, 1, 0));
  }
}

TEST(VoxelEmitters, PathTracedMirrorSeesTheVoxelWall) {
  // The MCPT baseline's scene: a mirror sphere reflects the voxelised red wall.
  const WallScene w(0.0f);
  VoxelGridSettings gs;
  gs.bounds = {vec3(-1.0f, -0.5f, -1.0f), vec3(1.0f, 1.5f, 1.0f)};
  gs.voxel_size = 0.02f;
  VoxelGrid grid(gs);
  grid.build(w.wall);
  const Model relic =
      holo::test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24, 48);
  const RenderScene scene(relic, {voxelEmitters(grid)});
  const Environment sky = Environment::uniform(vec3(0.5f));
  const PathTracer tracer(scene, sky);
  const cv::Mat image = renderPathTraced(tracer, w.view, 2);
  const vec3 centre = rgbAt(image, 24, 24);
  EXPECT_NEAR(centre.r, 0.9f * 2.0f, 0.15f);
  EXPECT_NEAR(centre.g, 0.0f, 0.05f);
}

}  // namespace
}  // namespace holo::reference
