// The frame renderer's passes one at a time (reflect/src): static shading, the foreground walk
// with its camera choice and near-miss march, the composition and the tone map of the covered
// pixels, each on a small analytic scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "compose_pass.hpp"
#include "foreground_walk.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "holo/reflect/voxel_walk.hpp"
#include "reflect_test_scenes.hpp"
#include "static_shading.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

// A metal sphere (F0 0.9) of radius 0.15 at (0, 0.3, 0) under a uniform sky of 0.5, seen from +z.
struct MirrorSphere {
  explicit MirrorSphere(float roughness = 0.0f)
      : scene(test::sphereModel({vec3(0.9f), 1.0f, roughness, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24, 48),
              {}),
        ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16}) {
    traceHitPoints(scene, view, AntiAliasing::None, hits);
  }
  RenderScene scene;
  PrefilteredIbl ibl;
  CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 48, 48);
  HitPointBuffer hits;
};

struct StaticResult {
  std::vector<SplitSumShading> shading;
  std::vector<WalkRay> walk_rays;
  cv::Mat hdr, coverage;
};

StaticResult shadeStatic(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                         const HitPointBuffer& hits, const CameraModel& view) {
  StaticResult r;
  r.hdr = cv::Mat(hits.height, hits.width, CV_32FC3, cv::Scalar::all(0));
  r.coverage = cv::Mat(hits.height, hits.width, CV_32FC1, cv::Scalar(0));
  ViewBounces bounces;
  StaticShading(scene, ibl, settings, nullptr)
      .shade(hits, view, r.shading, r.walk_rays, bounces, r.hdr, r.coverage);
  return r;
}

TEST(StaticShadingPass, MirrorSphereShowsTheSkyTimesItsReflectance) {
  const MirrorSphere m;
  const StaticResult r = shadeStatic(m.scene, m.ibl, test::smallGrid(), m.hits, m.view);
  // The centre: the sky (0.5) times the metal's F0 (0.9); off the sphere: black, no coverage.
  EXPECT_NEAR(rgbAt(r.hdr, 24, 24).g, 0.45f, 0.02f);
  EXPECT_FLOAT_EQ(r.coverage.at<float>(24, 24), 1.0f);
  EXPECT_EQ(rgbAt(r.hdr, 0, 0), vec3(0.0f));
  EXPECT_FLOAT_EQ(r.coverage.at<float>(0, 0), 0.0f);
  // A convex relic never meets itself: every walk ray is the hit point's own mirror ray.
  for (std::uint32_t p : m.hits.covered) {
    const WalkRay& w = r.walk_rays[p];
    EXPECT_FALSE(w.bounced);
    EXPECT_EQ(w.reflected, m.hits.hits[p].reflected);
  }
}

// Two mirror spheres side by side (bright left, dark right).
Model twoSpheres() {
  Model model = test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(-0.16f, 0.3f, 0.0f), 24, 48);
  const Model right =
      test::sphereModel({vec3(0.2f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.16f, 0.3f, 0.0f), 24, 48);
  model.meshes.push_back(right.meshes.front());
  model.meshes.back().material = 1;
  model.materials.push_back(right.materials.front());
  return model;
}

// The open upper half of a sphere of radius 0.15 at (0, 0.3, 0): a bowl, seen inside and out.
Model bowl() {
  Model model = test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24, 48);
  TriangleMesh& mesh = model.meshes.front();
  std::vector<uvec3> lower;
  for (const uvec3& t : mesh.triangles)
    if (mesh.positions[t.x].y <= 0.3f + 1e-6f && mesh.positions[t.y].y <= 0.3f + 1e-6f &&
        mesh.positions[t.z].y <= 0.3f + 1e-6f)
      lower.push_back(t);
  mesh.triangles = lower;
  model.materials.front().double_sided = true;  // its inside is seen
  return model;
}

// A trace that refines more pixels than the view's earlier ones (here every traced pixel, where
// the earlier one refined only the silhouette) fits in what the first reserved: neither the hit
// points nor the per-sample shading move, so no frame copies and faults them in anew.
TEST(StaticShadingPass, ATraceRefiningMorePixelsMovesNeitherTheHitsNorTheShading) {
  const MirrorSphere s;
  const TracerSettings settings;
  const StaticShading pass(s.scene, s.ibl, settings, nullptr);
  HitPointBuffer hits;
  std::vector<SplitSumShading> shading;
  std::vector<WalkRay> walk_rays;
  ViewBounces bounces;
  cv::Mat hdr(s.view.height(), s.view.width(), CV_32FC3, cv::Scalar::all(0));
  cv::Mat coverage(s.view.height(), s.view.width(), CV_32FC1, cv::Scalar(0));
  traceHitPoints(s.scene, s.view, AntiAliasing::Edges, hits, s.scene.relicBounds());
  pass.shade(hits, s.view, shading, walk_rays, bounces, hdr, coverage);
  const std::size_t edge_samples = hits.hits.size();
  const HitPoint* hit_storage = hits.hits.data();
  const std::uint8_t* valid_storage = hits.valid.data();
  const SplitSumShading* shading_storage = shading.data();
  const WalkRay* walk_storage = walk_rays.data();

  traceHitPoints(s.scene, s.view, AntiAliasing::Full, hits, s.scene.relicBounds());
  pass.shade(hits, s.view, shading, walk_rays, bounces, hdr, coverage);
  ASSERT_GT(hits.hits.size(), 2 * edge_samples);  // the sphere fills most of the view
  EXPECT_EQ(hits.hits.data(), hit_storage);
  EXPECT_EQ(hits.valid.data(), valid_storage);
  EXPECT_EQ(shading.data(), shading_storage);
  EXPECT_EQ(walk_rays.data(), walk_storage);
  EXPECT_EQ(shading.size(), hits.hits.size());
}

TEST(StaticShadingPass, InterreflectionStartsTheWalkOnTheSecondPoint) {
  // Two mirror spheres side by side, bright (F0 0.9) and dark (0.2): where one's limb mirrors the
  // other, its walk ray starts (bounced) on the other with the second point's reflection.
  const RenderScene scene(twoSpheres(), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.5f), vec3(0.0f, 0.3f, 0.0f), 30.0f, 64, 64);
  HitPointBuffer hits;
  traceHitPoints(scene, view, AntiAliasing::None, hits);
  TracerSettings on = test::smallGrid(), off = test::smallGrid();
  off.relic_interreflection = false;
  const StaticResult with = shadeStatic(scene, ibl, on, hits, view);
  const StaticResult without = shadeStatic(scene, ibl, off, hits, view);
  int bounced = 0, darker = 0;
  for (std::uint32_t p : hits.covered) {
    EXPECT_FALSE(without.walk_rays[p].bounced);
    if (!with.walk_rays[p].bounced) continue;
    ++bounced;
    // On the other sphere (each limb facing the other mirrors it).
    EXPECT_LT(with.walk_rays[p].position.x * hits.hits[p].position.x, 0.0f);
    // The other sphere's reflection of the sky (its reflectance multiplied in) instead of the sky;
    // the bright sphere's pixels show the dark one's F0 0.2.
    const int x = int(p % 64u), y = int(p / 64u);
    EXPECT_LE(rgbAt(with.hdr, x, y).g, rgbAt(without.hdr, x, y).g + 1e-6f);
    darker += rgbAt(with.hdr, x, y).g < 0.5f * rgbAt(without.hdr, x, y).g;
  }
  EXPECT_GT(bounced, 5);
  EXPECT_GT(darker, 5);
}

// The supporting planes skip only mirror rays that would miss: on every relic and view below,
// each hit point whose mirror ray is not cast has a ray that, cast, misses the relic; a convex
// relic casts almost none (only at its limbs, where the mirror ray about the smooth normal dips
// below the flat triangle's plane and the triangle cannot decide), and a concave one keeps the
// rays where it sees itself.
TEST(StaticShadingPass, InterreflectionSkipsOnlyMirrorRaysThatCannotMeetTheRelic) {
  struct Case {
    const char* name;
    Model model;
    vec3 eye;
    float max_cast_share, min_cast_share;
  };
  const Case cases[] = {
      {"sphere", test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24, 48),
       vec3(0.0f, 0.3f, 1.2f), 0.05f, 0.0f},
      {"two spheres", twoSpheres(), vec3(0.0f, 0.3f, 1.5f), 0.7f, 0.02f},
      {"bowl from above", bowl(), vec3(0.0f, 1.0f, 0.6f), 1.0f, 0.3f},
      {"bowl from below", bowl(), vec3(0.0f, -0.6f, 0.6f), 0.0f, 0.0f},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const RenderScene scene(c.model, {});
    const CameraModel view = lookAtCamera(c.eye, vec3(0.0f, 0.3f, 0.0f), 35.0f, 64, 64);
    HitPointBuffer hits;
    traceHitPoints(scene, view, AntiAliasing::None, hits);
    int cast = 0, skipped = 0;
    for (const std::uint32_t p : hits.covered) {
      const HitPoint& h = hits.hits[p];
      if (h.mirror_may_meet_relic) {
        ++cast;
        continue;
      }
      ++skipped;
      const Ray ray{h.position + h.normal * TracerSettings{}.ray_offset, h.reflected};
      EXPECT_FALSE(scene.relicOnly().intersect(ray).hit()) << "pixel " << p;
    }
    ASSERT_GT(cast + skipped, 200);
    const float share = float(cast) / float(cast + skipped);
    EXPECT_LE(share, c.max_cast_share);
    EXPECT_GE(share, c.min_cast_share);
  }
}

// Where no mirror ray is cast, the picture is the one the cast rays give: the two spheres'
// interreflection with the rays the planes skip cast anyway (their hit points marked) is the same
// image, to the bit.
TEST(StaticShadingPass, SkippedMirrorRaysLeaveThePictureUnchanged) {
  const RenderScene scene(twoSpheres(), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.5f), vec3(0.0f, 0.3f, 0.0f), 30.0f, 64, 64);
  HitPointBuffer hits;
  traceHitPoints(scene, view, AntiAliasing::None, hits);
  HitPointBuffer all_cast = hits;
  int marked = 0;
  for (HitPoint& h : all_cast.hits) {
    marked += h.mirror_may_meet_relic ? 0 : 1;
    h.mirror_may_meet_relic = true;
  }
  ASSERT_GT(marked, 100);
  const StaticResult skipping = shadeStatic(scene, ibl, test::smallGrid(), hits, view);
  const StaticResult casting = shadeStatic(scene, ibl, test::smallGrid(), all_cast, view);
  EXPECT_EQ(cv::norm(skipping.hdr, casting.hdr, cv::NORM_INF), 0.0);
}

TEST(NearMissMarch, FindsTheFirstPointWithinTheRadiusOfAnOccupiedBrick) {
  const TracerSettings s = test::smallGrid();
  VoxelGrid grid(s.grid);
  ForegroundCloud cloud;
  ForegroundPoint p;
  p.position = vec3(0.01f, 0.51f, 0.01f);
  cloud.points.push_back(p);
  grid.build(cloud);
  // Passing 0.3 m beside the point, along +x from 0.9 m before it.
  const Ray ray{vec3(-0.9f, 0.51f, 0.31f), vec3(1.0f, 0.0f, 0.0f)};
  EXPECT_FALSE(nearMissT(grid, ray, 2.0f, 0.0f));  // nowhere near at radius 0
  // Within the grid (t < 1.9) 0.1 t stays below the 3 empty bricks (0.24 m) around the point's.
  EXPECT_FALSE(nearMissT(grid, ray, 2.0f, 0.1f));
  const std::optional<float> t = nearMissT(grid, ray, 2.0f, 0.5f);
  ASSERT_TRUE(t);
  // 0.5 t first reaches the empty bricks' 0.24 m near t = 0.5: never before 0.3, nor past the point.
  EXPECT_GT(*t, 0.3f);
  EXPECT_LT(*t, 0.9f);
  const float distance = glm::length(ray.origin + *t * ray.direction - p.position);
  EXPECT_LE(distance, 0.5f * *t + 2.0f * 0.08f * std::sqrt(3.0f));
  // Away from the point: never.
  EXPECT_FALSE(nearMissT(grid, Ray{ray.origin, -ray.direction}, 2.0f, 0.5f));
}

// A wall of red points at z = 0.6 with a 4 cm hole around (0.005, 0.31): a rough ray along +z
// through the hole meets no voxel, though its bricks hold the wall. The one camera stands 0.1 m
// in front of the wall looking at it, so it sees the wall but nothing nearer the relic.
struct HoledWall {
  HoledWall() {
    const test::RedWall full = test::redWall();
    for (const ForegroundPoint& p : full.cloud.points)
      if (std::abs(p.position.x - 0.005f) > 0.025f || std::abs(p.position.y - 0.31f) > 0.025f)
        cloud.points.push_back(p);
    camera = full.camera;
    camera.camera = lookAtCamera(vec3(0.0f, 0.3f, 0.5f), vec3(0.0f, 0.3f, 0.6f), 100.0f, 64, 64);
    grid.build(cloud);
  }
  TracerSettings settings = test::smallGrid();
  VoxelGrid grid{settings.grid};
  ForegroundCloud cloud;
  ForegroundCameraImage camera;
  Ray ray{vec3(0.005f, 0.305f, 0.15f), vec3(0.0f, 0.0f, 1.0f)};
};

TEST(NearMissMarch, ReadsWhereARaySlippingThroughAGapPassesTheVisitor) {
  const HoledWall w;
  ASSERT_FALSE(firstOccupiedVoxel(w.grid, w.ray, 2.0f).hit());  // through the hole
  // A lobe of roughness 0.45 (2 tan(sigma) = 0.59 per metre): the first near point lies bricks
  // in front of the wall (z < 0.52), the nearest pass in the wall's brick (z in [0.6, 0.68)).
  const float radius = 2.0f * std::tan(reflectedLobeSigma(0.45f));
  const std::optional<float> t_near = nearMissT(w.grid, w.ray, 2.0f, radius);
  ASSERT_TRUE(t_near);
  EXPECT_LT(w.ray.origin.z + *t_near, 0.52f);
  const float z = w.ray.origin.z + nearestPassT(w.grid, w.ray, *t_near, 2.0f);
  EXPECT_GE(z, 0.6f);
  EXPECT_LT(z, 0.68f);
  // Past the wall's edge (0.5 m beside it, parallel to it) the brick distance stays that of the
  // x offset from the first near point on: the first near point is the nearest pass.
  const Ray beside{vec3(0.9f, 0.3f, -0.4f), vec3(0.0f, 0.0f, 1.0f)};
  const std::optional<float> t_beside = nearMissT(w.grid, beside, 2.0f, radius);
  ASSERT_TRUE(t_beside);
  EXPECT_FLOAT_EQ(nearestPassT(w.grid, beside, *t_beside, 2.0f), *t_beside);
}

TEST(ForegroundWalkPass, ARoughRaySlippingThroughAGapReadsTheVisitorACameraSees) {
  const HoledWall w;
  const std::vector<ForegroundCameraImage> cameras = {w.camera};
  std::vector<ForegroundPyramid> pyramids(1);
  pyramids[0].build(w.camera.colour_bgr, w.camera.mask, w.settings.pyramid_levels);
  // The first near point (z < 0.52) is behind the camera: no camera sees it. The walk reads the
  // wall where the ray passes it, in its red, instead of dropping the visitor.
  ASSERT_FALSE(cameraAlong(cameras, pyramids, w.ray.origin + 0.35f * w.ray.direction, w.ray.direction));
  const ForegroundWalk walk(w.settings, w.grid, pyramids, cameras, nullptr);
  ForegroundSample sample;
  ASSERT_TRUE(walk.walk(w.ray.origin, w.ray.direction, w.ray.direction, 0.45f, sample));
  EXPECT_NEAR(sample.radiance.r, 2.0f, 0.05f);
  EXPECT_NEAR(sample.radiance.g, 0.0f, 0.01f);
  EXPECT_GT(sample.weight, 0.5f);
}

// A thin arm before a body: a red rod 3 cm thick at z = 0.3 (y 0.1-0.5), seen only by camera 0,
// from the side (+x), against nothing; a blue wall at z = 0.6 behind it, seen only by camera 1.
// A rough ray along +z from the origin meets the rod; its lobe is far wider than the rod.
struct ArmBeforeBody {
  ArmBeforeBody() {
    cameras[0].camera = lookAtCamera(vec3(0.5f, 0.3f, 0.3f), vec3(0.0f, 0.3f, 0.3f), 60.0f, 64, 64);
    cameras[0].colour_bgr = cv::Mat(64, 64, CV_32FC3, cv::Scalar::all(0));
    cameras[0].mask = cv::Mat(64, 64, CV_32FC1, cv::Scalar(0));
    for (float y = 0.1f; y <= 0.5f; y += 0.005f)
      for (float z = 0.285f; z <= 0.315f; z += 0.005f) add(0, vec3(0.0f, y, z), vec3(2.0f, 0.0f, 0.0f));
    cameras[1].camera = lookAtCamera(vec3(0.0f, 0.3f, 0.0f), vec3(0.0f, 0.3f, 0.6f), 100.0f, 64, 64);
    cameras[1].colour_bgr = cv::Mat(64, 64, CV_32FC3, cv::Scalar(2, 0, 0));  // blue, linear BGR
    cameras[1].mask = cv::Mat(64, 64, CV_32FC1, cv::Scalar(1));
    for (float x = -0.3f; x <= 0.3f; x += 0.01f)
      for (float y = 0.0f; y <= 0.6f; y += 0.01f) add(1, vec3(x, y, 0.6f), vec3(0.0f, 0.0f, 2.0f));
    grid.build(cloud);
    for (std::size_t c = 0; c < 2; ++c)
      pyramids[c].build(cameras[c].colour_bgr, cameras[c].mask, settings.pyramid_levels);
  }
  // A point of camera c, splatted into camera 0's image (camera 1's is full already).
  void add(std::uint16_t c, const vec3& position, const vec3& radiance) {
    ForegroundPoint p;
    p.position = position;
    p.radiance = radiance;
    p.camera = c;
    const std::optional<vec2> px = cameras[c].camera.project(position);
    if (!px) return;
    p.x = std::uint16_t(std::clamp(px->x, 0.0f, 63.0f));
    p.y = std::uint16_t(std::clamp(px->y, 0.0f, 63.0f));
    cloud.points.push_back(p);
    if (c != 0) return;
    cameras[0].mask.at<float>(p.y, p.x) = 1.0f;
    cameras[0].colour_bgr.at<cv::Vec3f>(p.y, p.x) = cv::Vec3f(radiance.b, radiance.g, radiance.r);
  }
  TracerSettings settings = test::smallGrid();
  VoxelGrid grid{settings.grid};
  ForegroundCloud cloud;
  std::vector<ForegroundCameraImage> cameras = std::vector<ForegroundCameraImage>(2);
  std::vector<ForegroundPyramid> pyramids = std::vector<ForegroundPyramid>(2);
};

TEST(ForegroundWalkPass, ARoughRayMeetingAThinArmReadsTheBodyBehindIt) {
  const ArmBeforeBody a;
  const float roughness = 0.35f;
  const Ray ray{vec3(0.0f, 0.3f, 0.0f), vec3(0.0f, 0.0f, 1.0f)};
  const VoxelHit front = firstOccupiedVoxel(a.grid, ray, 2.0f);
  ASSERT_TRUE(front.hit());
  ASSERT_LT(front.t, 0.32f);  // the arm, not the wall
  // Camera 0 sees the arm against nothing: at the lobe's level its blurred mask covers a fraction.
  const CameraModel& side = a.cameras[0].camera;
  const vec3 at = ray.origin + ray.direction * front.t;
  const float level = foregroundLevel(roughness, front.t, glm::length(at - side.position()),
                                      side.intrinsics().fx, a.settings.pyramid_levels);
  EXPECT_LT(a.pyramids[0].sample(*side.project(at), level).weight, 0.6f);
  // The relic's lobe sees the wall all around the arm: the walk reads it behind the arm, the
  // lobe fully covered, the arm's red inside the wall's blue.
  const ForegroundWalk walk(a.settings, a.grid, a.pyramids, a.cameras, nullptr);
  ForegroundSample sample;
  ASSERT_TRUE(walk.walk(ray.origin, ray.direction, ray.direction, roughness, sample));
  EXPECT_GT(sample.weight, 0.95f);
  EXPECT_GT(sample.radiance.r, 0.1f);
  EXPECT_GT(sample.radiance.b, 1.0f);
  EXPECT_NEAR(sample.radiance.r + sample.radiance.b, 2.0f, 0.05f);
  // Beside the arm the ray meets the wall alone, in its blue.
  ASSERT_TRUE(walk.walk(vec3(0.15f, 0.3f, 0.0f), ray.direction, ray.direction, roughness, sample));
  EXPECT_NEAR(sample.weight, 1.0f, 0.01f);
  EXPECT_NEAR(sample.radiance.b, 2.0f, 0.05f);
  EXPECT_NEAR(sample.radiance.r, 0.0f, 0.01f);
}

// A visitor's surface seen at a slant: a red plate of points at z = 0.339 (x in [-0.05, 0.05], y
// in [0.25, 0.35]), inside the voxels z in [0.32, 0.34) of the 2 cm grid, seen only by a camera
// on its -x side. A mirror ray along +z enters those voxels 1.9 cm in front of the plate, where
// the camera's line of sight passes beside the plate's +x edge.
struct SlantedPlate {
  SlantedPlate() {
    camera.camera = lookAtCamera(vec3(-0.6f, 0.305f, -0.1f), vec3(0.0f, 0.305f, 0.339f), 30.0f, 256, 256);
    camera.colour_bgr = cv::Mat(256, 256, CV_32FC3, cv::Scalar::all(0));
    camera.mask = cv::Mat(256, 256, CV_32FC1, cv::Scalar(0));
    for (float x = -0.05f; x <= 0.05f; x += 0.001f)
      for (float y = 0.25f; y <= 0.35f; y += 0.001f) {
        ForegroundPoint p;
        p.position = vec3(x, y, 0.339f);
        p.radiance = vec3(2.0f, 0.0f, 0.0f);
        const std::optional<vec2> px = camera.camera.project(p.position);
        if (!px) continue;
        p.x = std::uint16_t(std::clamp(px->x, 0.0f, 255.0f));
        p.y = std::uint16_t(std::clamp(px->y, 0.0f, 255.0f));
        cloud.points.push_back(p);
        camera.mask.at<float>(p.y, p.x) = 1.0f;
        camera.colour_bgr.at<cv::Vec3f>(p.y, p.x) = cv::Vec3f(0.0f, 0.0f, 2.0f);
      }
    grid.build(cloud);
    pyramids[0].build(camera.colour_bgr, camera.mask, settings.pyramid_levels);
  }
  TracerSettings settings = test::smallGrid();
  VoxelGrid grid{settings.grid};
  ForegroundCloud cloud;
  ForegroundCameraImage camera;
  std::vector<ForegroundPyramid> pyramids = std::vector<ForegroundPyramid>(1);
};

TEST(ForegroundWalkPass, AMirrorRayEnteringTheVoxelsBesideTheSilhouetteMeetsTheVisitorBehind) {
  const SlantedPlate s;
  const std::vector<ForegroundCameraImage> cameras = {s.camera};
  const ForegroundWalk walk(s.settings, s.grid, s.pyramids, cameras, nullptr);
  const vec3 along(0.0f, 0.0f, 1.0f);
  // 9 mm inside the plate's edge: the voxels are entered at z = 0.32, and half a voxel in the
  // camera sees the point beside the plate (its line of sight meets z = 0.339 at x = 0.055).
  const Ray inside{vec3(0.041f, 0.305f, 0.0f), along};
  const VoxelHit entered = firstOccupiedVoxel(s.grid, inside, 2.0f);
  ASSERT_TRUE(entered.hit());
  EXPECT_NEAR(inside.origin.z + entered.t, 0.32f, 1e-3f);
  const vec3 half_in = inside.origin + inside.direction * (entered.t + 0.01f);
  ASSERT_LT(s.pyramids[0].sample(*s.camera.camera.project(half_in), 0.0f).weight, 0.01f);
  // The ray is followed on through the voxels to where it meets the plate: the visitor, in red.
  ForegroundSample sample;
  ASSERT_TRUE(walk.walk(inside.origin, along, along, 0.0f, sample));
  EXPECT_GT(sample.weight, 0.9f);
  EXPECT_NEAR(sample.radiance.r, 2.0f, 0.05f);
  EXPECT_NEAR(sample.radiance.g, 0.0f, 0.01f);
  // 5 mm beside the edge, through the same voxels: its path stays outside the silhouette, and the
  // ray that misses the plate still reads none of it.
  const Ray beside{vec3(0.055f, 0.305f, 0.0f), along};
  ASSERT_TRUE(firstOccupiedVoxel(s.grid, beside, 2.0f).hit());
  ForegroundSample none;
  walk.walk(beside.origin, along, along, 0.0f, none);
  EXPECT_LT(none.weight, 0.01f);
}

TEST(CameraChoice, TakesTheCameraLookingMostAlongTheRayThatSeesThePoint) {
  std::vector<ForegroundCameraImage> cameras(2);
  cameras[0].camera = lookAtCamera(vec3(0.0f, 0.0f, 2.0f), vec3(0.0f), 60.0f, 16, 16);  // looks along -z
  cameras[1].camera = lookAtCamera(vec3(2.0f, 0.0f, 0.0f), vec3(0.0f), 60.0f, 16, 16);  // looks along -x
  const cv::Mat colour(16, 16, CV_32FC3, cv::Scalar::all(1)), mask(16, 16, CV_32FC1, cv::Scalar(1));
  std::vector<ForegroundPyramid> pyramids(2);
  for (ForegroundPyramid& p : pyramids) p.build(colour, mask, 2);
  const auto along = [&](const vec3& point, const vec3& direction) {
    return cameraAlong(cameras, pyramids, point, direction);
  };
  ASSERT_TRUE(along(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f)));
  EXPECT_EQ(along(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f))->camera, 0u);
  EXPECT_EQ(along(vec3(0.0f), vec3(-1.0f, 0.0f, 0.0f))->camera, 1u);
  EXPECT_NEAR(along(vec3(0.0f), vec3(-1.0f, 0.0f, 0.0f))->pixel.x, 7.5f, 0.6f);  // the image centre
  // Behind the first camera and outside the second's image: no camera sees the point.
  EXPECT_FALSE(along(vec3(0.0f, 0.0f, 2.5f), vec3(0.0f, 0.0f, -1.0f)));
  // A camera without an image this frame is never chosen.
  pyramids[0].clear();
  EXPECT_EQ(along(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f))->camera, 1u);
  pyramids[1].clear();
  EXPECT_FALSE(along(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f)));
}

// A red wall (test::redWall() unless given) voxelised on the small grid, seen by its camera, and a
// walk over it.
struct RedWallWalk {
  explicit RedWallWalk(test::RedWall red_wall = test::redWall()) : wall(std::move(red_wall)) {
    grid.build(wall.cloud);
    pyramids[0].build(wall.camera.colour_bgr, wall.camera.mask, settings.pyramid_levels);
  }
  const TracerSettings settings = test::smallGrid();
  const test::RedWall wall;
  VoxelGrid grid{settings.grid};
  const std::vector<ForegroundCameraImage> cameras = {wall.camera};
  std::vector<ForegroundPyramid> pyramids = std::vector<ForegroundPyramid>(1);
  const ForegroundWalk walk{settings, grid, pyramids, cameras, nullptr};
};

TEST(ForegroundWalkPass, MirrorRaysMeetTheWallInItsColour) {
  const MirrorSphere m;
  const RedWallWalk w;
  const TracerSettings& s = w.settings;
  const ForegroundWalk& walk = w.walk;
  // Straight back from the sphere's front: the wall, red.
  ForegroundSample sample;
  ASSERT_TRUE(walk.walk(vec3(0.0f, 0.3f, 0.15f), vec3(0, 0, 1), vec3(0, 0, 1), 0.0f, sample));
  EXPECT_NEAR(sample.radiance.r, 2.0f, 0.05f);
  EXPECT_NEAR(sample.radiance.g, 0.0f, 0.01f);
  EXPECT_NEAR(sample.weight, 1.0f, 0.01f);
  // Away from the wall: nothing, the sample untouched.
  ForegroundSample none;
  EXPECT_FALSE(walk.walk(vec3(0.0f, 0.3f, -0.15f), vec3(0, 0, -1), vec3(0, 0, -1), 0.0f, none));
  EXPECT_EQ(none.weight, 0.0f);
  // A whole view: the centre pixel meets the wall, the corners are not the relic's.
  const StaticResult st = shadeStatic(m.scene, m.ibl, s, m.hits, m.view);
  std::vector<ForegroundSample> fg(m.hits.hits.size());
  WalkScratch scratch;
  const WalkCounts counts = walk.walkView(m.hits, st.walk_rays, scratch, fg);
  EXPECT_EQ(counts.walked, m.hits.covered.size());  // one sample per pixel: one walk each
  EXPECT_GT(counts.found, 0u);
  EXPECT_LT(counts.found, counts.walked);  // rays near the rim pass beside the wall
  EXPECT_NEAR(fg[24 * 48 + 24].radiance.r, 2.0f, 0.05f);
  EXPECT_EQ(fg[0].weight, 0.0f);
}

// walkView tests its rays against the occupied voxels' box and the boxes of the grid's occupied
// groups before walking them: every pixel's result must be the walk's own. Each pixel of the sphere
// gets an adversarial ray: along an axis (zero direction components), starting on the planes of
// one of those boxes or of the box grown by a voxel, grazing their edges, from inside a box, or
// anywhere; some rough enough that a miss still reads the visitors it passes near.
void expectUnwalkedRaysAreTheMisses(const RedWallWalk& w) {
  const MirrorSphere m;
  const TracerSettings& s = w.settings;
  const VoxelGrid& grid = w.grid;
  const ForegroundWalk& walk = w.walk;
  StaticResult st = shadeStatic(m.scene, m.ibl, s, m.hits, m.view);
  const float voxel = grid.voxelSize();
  std::vector<VoxelGrid::VoxelBox> boxes = {{grid.occupiedLo(), grid.occupiedHi()}};
  boxes.insert(boxes.end(), grid.occupiedGroups().begin(), grid.occupiedGroups().end());
  const vec3 axes[6] = {vec3(1, 0, 0),  vec3(-1, 0, 0), vec3(0, 1, 0),
                        vec3(0, -1, 0), vec3(0, 0, 1),  vec3(0, 0, -1)};
  std::uint32_t state = 12345u;
  const auto uniform = [&] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (const std::uint32_t p : m.hits.covered) {
    const VoxelGrid::VoxelBox& box = boxes[p / 7 % boxes.size()];
    const vec3 lo = grid.origin() + vec3(box.lo) * voxel, hi = grid.origin() + vec3(box.hi) * voxel;
    const vec3 planes[4] = {lo, hi, lo - vec3(voxel), hi + vec3(voxel)};
    const vec3 centre = 0.5f * (lo + hi), extent = hi - lo;
    WalkRay& ray = st.walk_rays[p];
    const int kind = int(p % 5);
    vec3 origin = centre + (vec3(uniform(), uniform(), uniform()) - 0.5f) * 3.0f * extent;
    vec3 direction = glm::normalize(vec3(uniform(), uniform(), uniform()) - 0.5f);
    if (kind == 0) {  // along an axis, from a point on one of the boxes' planes
      direction = axes[p % 6];
      const int a = int(p / 6 % 3);
      origin[a] = planes[p / 18 % 4][a];
    } else if (kind == 1) {  // towards a corner or an edge of a box
      const vec3& plane_lo = planes[p % 2 == 0 ? 0 : 2];
      const vec3& plane_hi = planes[p % 2 == 0 ? 1 : 3];
      const vec3 corner(p % 3 == 0 ? plane_lo.x : plane_hi.x, p % 7 < 3 ? plane_lo.y : plane_hi.y,
                        p % 11 < 5 ? plane_lo.z : plane_hi.z);
      direction = glm::normalize(corner - origin);
    } else if (kind == 2) {  // from inside the box
      origin = lo + vec3(uniform(), uniform(), uniform()) * extent;
    }
    // The ray starts ray_offset along the normal; with the normal along the direction the ray is
    // exactly origin + t direction.
    ray.normal = direction;
    ray.reflected = direction;
    ray.position = origin - direction * s.ray_offset;
    ray.roughness = p % 4 == 0 ? s.lobe_fallback_roughness : 0.0f;
    ray.bounced = false;
  }
  std::vector<ForegroundSample> fg(m.hits.hits.size());
  WalkScratch scratch;
  const WalkCounts counts = walk.walkView(m.hits, st.walk_rays, scratch, fg);
  EXPECT_EQ(counts.walked, m.hits.covered.size());
  std::uint64_t met = 0, missed = 0;
  for (const std::uint32_t p : m.hits.covered) {
    const WalkRay& ray = st.walk_rays[p];
    ForegroundSample expected;
    const bool hit = walk.walk(ray.position * 1.0f, ray.normal / glm::length(ray.normal),
                               ray.reflected / glm::length(ray.reflected), ray.roughness * 1.0f, expected);
    (hit ? met : missed) += 1;
    EXPECT_EQ(fg[p].weight, hit ? expected.weight : 0.0f) << "pixel " << p;
    EXPECT_EQ(fg[p].radiance, hit ? expected.radiance : vec3(0.0f)) << "pixel " << p;
  }
  EXPECT_EQ(met, counts.found);
  // Both outcomes are well represented.
  EXPECT_GT(met, m.hits.covered.size() / 20);
  EXPECT_GT(missed, m.hits.covered.size() / 4);
}

TEST(ForegroundWalkPass, RaysLeftUnwalkedBesideTheVisitorsBoxAreExactlyTheMisses) {
  const RedWallWalk w;
  ASSERT_EQ(w.grid.occupiedGroups().size(), 1u);
  expectUnwalkedRaysAreTheMisses(w);
}

TEST(ForegroundWalkPass, RaysLeftUnwalkedBetweenVisitorsStandingApartAreExactlyTheMisses) {
  // Three pieces of the wall apart (left, right, above the middle), as three visitors: the grid's
  // groups leave out the space between them, which the one occupied box spans.
  test::RedWall walls = test::redWall(-0.5f, 0.0f, 21, 41);
  for (const test::RedWall& more : {test::redWall(0.3f, 0.0f, 21, 41), test::redWall(-0.1f, 0.6f, 21, 11)})
    walls.cloud.points.insert(walls.cloud.points.end(), more.cloud.points.begin(), more.cloud.points.end());
  const RedWallWalk w(walls);
  ASSERT_EQ(w.grid.occupiedGroups().size(), 3u);
  expectUnwalkedRaysAreTheMisses(w);
}

TEST(CompositionPass, ComposesOnlyWhereTheForegroundReachedAndTonemapsThose) {
  const MirrorSphere m;
  const StaticResult st = shadeStatic(m.scene, m.ibl, test::smallGrid(), m.hits, m.view);
  std::vector<ForegroundSample> fg(m.hits.hits.size());
  const std::size_t lit = 24 * 48 + 24;
  fg[lit] = {vec3(2.0f, 0.0f, 0.0f), 1.0f};
  cv::Mat hdr = st.hdr.clone(), weight(48, 48, CV_32FC1, cv::Scalar(0));
  cv::Mat display = toneMapCovered(hdr, m.hits.covered, 1.0f);
  EXPECT_EQ(composeForeground(m.hits, st.shading, fg, 1.0f, hdr, weight, display), 1u);
  // w = 1: the specular is the foreground's alone, plus the diffuse (none for a metal).
  const SplitSumShading& sh = st.shading[lit];
  const vec3 expected = sh.specular_scale * vec3(2.0f, 0.0f, 0.0f) + sh.diffuse;
  EXPECT_NEAR(rgbAt(hdr, 24, 24).r, expected.r, 1e-5f);
  EXPECT_NEAR(rgbAt(hdr, 24, 24).g, expected.g, 1e-5f);
  EXPECT_FLOAT_EQ(weight.at<float>(24, 24), 1.0f);
  EXPECT_EQ(display.at<cv::Vec3b>(24, 24), toneMapPixel(expected, 1.0f));
  // Every other pixel keeps the static image.
  EXPECT_EQ(rgbAt(hdr, 23, 24), rgbAt(st.hdr, 23, 24));
  EXPECT_FLOAT_EQ(weight.at<float>(24, 23), 0.0f);
  // Without a tone map (exposure 0) the display is left alone.
  cv::Mat untouched;
  EXPECT_EQ(composeForeground(m.hits, st.shading, fg, 0.0f, hdr, weight, untouched), 1u);
  EXPECT_TRUE(untouched.empty());
}

TEST(ToneMapPass, MapsTheCoveredPixelsAndLeavesTheRestBlack) {
  cv::Mat hdr(4, 4, CV_32FC3, cv::Scalar::all(0.5));
  const std::vector<std::uint32_t> covered = {1, 6, 15};
  const cv::Mat display = toneMapCovered(hdr, covered, 2.0f);
  ASSERT_EQ(display.type(), CV_8UC3);
  const cv::Vec3b mapped = toneMapPixel(vec3(0.5f), 2.0f);
  EXPECT_NE(mapped, cv::Vec3b(0, 0, 0));
  for (int p = 0; p < 16; ++p) {
    const bool in = p == 1 || p == 6 || p == 15;
    EXPECT_EQ(display.at<cv::Vec3b>(p / 4, p % 4), in ? mapped : cv::Vec3b(0, 0, 0)) << p;
  }
}

}  // namespace
}  // namespace holo::reflect
