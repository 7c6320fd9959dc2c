// The frame renderer end to end on a mirror sphere with a red "visitor" in front of it, the effect
// plan, and the composition's bounds.
#include "holo/reflect/frame_renderer.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/composition.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNan = std::numeric_limits<float>::quiet_NaN();

TEST(Composition, MixesAndStaysFiniteAndBounded) {
  const vec3 d(2.0f, 0.0f, 1.0f), s(0.0f, 1.0f, 1.0f);
  const vec3 mid = composeReflection(d, s, 0.25f);
  EXPECT_FLOAT_EQ(mid.r, 0.5f);
  EXPECT_FLOAT_EQ(mid.g, 0.75f);
  EXPECT_FLOAT_EQ(mid.b, 1.0f);
  EXPECT_EQ(composeReflection(d, s, 0.0f), s);
  EXPECT_EQ(composeReflection(d, s, 1.0f), d);
  EXPECT_EQ(composeReflection(d, s, 7.0f), d);   // w clamped to 1
  EXPECT_EQ(composeReflection(d, s, -3.0f), s);  // w clamped to 0
  EXPECT_EQ(composeReflection(d, s, kNan), s);   // NaN weight: no foreground
  EXPECT_EQ(composeReflection(d, s, kInf), s);   // so is an infinite one
  for (float w : {kNan, kInf, -kInf, 0.5f}) {
    const vec3 c = composeReflection(vec3(kNan, kInf, -1.0f), vec3(-kInf, kNan, 3.0f), w);
    EXPECT_TRUE(isFinite(c));
    EXPECT_GE(glm::min(c.x, glm::min(c.y, c.z)), 0.0f);
    EXPECT_LE(c.b, 3.0f);
  }
}

EffectInputs nearForeground() {
  EffectInputs in;
  in.foreground_points = 100;
  in.cameras = 4;
  in.relic_bounds = {vec3(-0.1f), vec3(0.1f)};
  in.foreground_bounds = {vec3(0.5f), vec3(1.0f)};
  return in;
}

TEST(EffectPlan, ForegroundPassesRunOnlyWhenTheyCanMatter) {
  const EffectPlan full = planEffects(nearForeground());
  for (Pass p : {Pass::VoxelGrid, Pass::Pyramids, Pass::HitPoints, Pass::StaticReflections,
                 Pass::ForegroundWalk, Pass::Composition, Pass::ToneMap})
    EXPECT_TRUE(full.has(p)) << passName(p);
  auto expectStaticOnly = [](const EffectInputs& in, const std::string& reason) {
    const EffectPlan plan = planEffects(in);
    EXPECT_EQ(plan.foreground_reason, reason);
    for (Pass p : {Pass::VoxelGrid, Pass::Pyramids, Pass::ForegroundWalk, Pass::Composition})
      EXPECT_FALSE(plan.has(p)) << passName(p) << " runs although " << reason;
    EXPECT_TRUE(plan.has(Pass::HitPoints));
    EXPECT_TRUE(plan.has(Pass::StaticReflections));
  };
  EffectInputs in = nearForeground();
  in.foreground_enabled = false;
  expectStaticOnly(in, "foreground effect off");
  in = nearForeground();
  in.foreground_points = 0;
  expectStaticOnly(in, "no foreground points");
  in = nearForeground();
  in.cameras = 0;
  expectStaticOnly(in, "no foreground cameras");
  in = nearForeground();
  in.relic_glossy = false;
  expectStaticOnly(in, "no glossy relic material");
  in = nearForeground();
  in.foreground_bounds = {vec3(5.0f), vec3(6.0f)};
  expectStaticOnly(in, "foreground beyond the reflection distance");
  in = nearForeground();
  in.relic_empty = true;
  const EffectPlan none = planEffects(in);
  EXPECT_EQ(none.passes, std::vector<Pass>{Pass::ToneMap});
  EXPECT_NE(full.describe().find("ForegroundWalk"), std::string::npos);
}

// A mirror-like sphere at (0, 0.3, 0), a uniform grey sky, and test::redWall(): a red wall of
// foreground points between the sphere and the viewer (visible only in the reflection), seen by
// one camera behind the sphere.
struct MirrorScene {
  explicit MirrorScene(float roughness)
      : scene(holo::test::sphereModel({vec3(0.9f), 1.0f, roughness, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24,
                                      48),
              {}),
        ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16}) {
    const holo::test::RedWall red = holo::test::redWall();
    camera = red.camera;
    wall = red.cloud;
    view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 48, 48);
  }
  RenderScene scene;
  PrefilteredIbl ibl;
  ForegroundCameraImage camera;
  ForegroundCloud wall;
  CameraModel view;
};

void expectFiniteAndBounded(const ViewImages& v) {
  for (int y = 0; y < v.hdr.rows; ++y)
    for (int x = 0; x < v.hdr.cols; ++x) {
      const vec3 c = rgbAt(v.hdr, x, y);
      ASSERT_TRUE(isFinite(c)) << x << "," << y;
      ASSERT_GE(glm::min(c.x, glm::min(c.y, c.z)), 0.0f);
      ASSERT_GE(v.weight.at<float>(y, x), 0.0f);
      ASSERT_LE(v.weight.at<float>(y, x), 1.0f);
      ASSERT_GE(v.coverage.at<float>(y, x), 0.0f);
      ASSERT_LE(v.coverage.at<float>(y, x), 1.0f);
    }
  EXPECT_EQ(v.display.type(), CV_8UC3);
}

TEST(FrameRenderer, MirrorShowsTheVisitorWhereTheReflectionMeetsIt) {
  MirrorScene m(0.0f);
  FrameRenderer renderer(m.scene, m.ibl, test::smallGrid());
  const FrameResult with = renderer.render(m.wall, {m.camera}, {m.view});
  ASSERT_TRUE(with.plan.has(Pass::ForegroundWalk)) << with.plan.describe();
  const ViewImages& v = with.views.at(0);
  expectFiniteAndBounded(v);
  // The sphere's centre reflects straight back at the wall: red, scaled by the metal's F0 (0.9).
  const vec3 centre = rgbAt(v.hdr, 24, 24);
  EXPECT_NEAR(centre.r, 0.9f * 2.0f, 0.15f);
  EXPECT_NEAR(centre.g, 0.0f, 0.05f);
  EXPECT_NEAR(v.weight.at<float>(24, 24), 1.0f, 1e-3f);
  EXPECT_EQ(v.coverage.at<float>(24, 24), 1.0f);
  EXPECT_EQ(v.coverage.at<float>(0, 0), 0.0f);
  EXPECT_EQ(rgbAt(v.hdr, 0, 0), vec3(0.0f));
  EXPECT_GT(v.foreground_hits, 0u);
  EXPECT_LT(v.foreground_hits, v.walked_rays);  // rays near the rim reflect past the wall
  // Some pixel is a partly covered silhouette.
  bool partial = false;
  for (int x = 0; x < 48; ++x) {
    const float c = v.coverage.at<float>(24, x);
    partial |= c > 0.0f && c < 1.0f;
  }
  EXPECT_TRUE(partial);

  // Without foreground the walk does not run and the centre shows the grey sky.
  const FrameResult without = renderer.render(ForegroundCloud{}, {m.camera}, {m.view});
  EXPECT_FALSE(without.plan.has(Pass::ForegroundWalk));
  EXPECT_TRUE(without.frame_timings.empty());
  for (const PassTiming& t : without.views.at(0).timings) {
    EXPECT_NE(t.pass, Pass::ForegroundWalk);
    EXPECT_NE(t.pass, Pass::Composition);
  }
  const vec3 sky = rgbAt(without.views.at(0).hdr, 24, 24);
  EXPECT_NEAR(sky.g, 0.9f * 0.5f, 0.05f);
  EXPECT_NEAR(sky.r, sky.g, 1e-3f);
  EXPECT_EQ(without.views.at(0).walked_rays, 0u);
}

TEST(FrameRenderer, StaysFiniteInHardCases) {
  for (float roughness : {0.0f, 0.5f, 1.0f}) {
    MirrorScene m(roughness);
    TracerSettings s = test::smallGrid();
    s.aa_samples = 1;
    FrameRenderer renderer(m.scene, m.ibl, s);
    // A visitor touching the pyramid (points on the relic's surface), points outside the grid,
    // NaN positions and a camera index with no image.
    ForegroundCloud cloud = m.wall;
    for (int i = 0; i < 200; ++i) {
      ForegroundPoint p;
      const float a = 0.05f * float(i);
      p.position = vec3(0.0f, 0.3f, 0.0f) + 0.15f * vec3(std::cos(a), 0.0f, std::sin(a));
      p.radiance = vec3(kInf, 1.0f, 0.0f);
      cloud.points.push_back(p);
    }
    ForegroundPoint far_point;
    far_point.position = vec3(50.0f);
    cloud.points.push_back(far_point);
    ForegroundPoint other_camera;
    other_camera.position = vec3(0.0f, 0.3f, 0.3f);
    other_camera.camera = 9;
    cloud.points.push_back(other_camera);
    ForegroundCameraImage bad = m.camera;
    bad.colour_bgr = cv::Mat(64, 64, CV_32FC3, cv::Scalar(kNan, kInf, 1));
    const FrameResult r = renderer.render(cloud, {bad}, {m.view});
    // Roughness 1 is not glossy: the walk is skipped, the output still bounded.
    ASSERT_EQ(r.plan.has(Pass::ForegroundWalk), roughness < kGlossyRoughnessLimit);
    expectFiniteAndBounded(r.views.at(0));
  }
}

TEST(FrameRenderer, EdgeWalkMatchesAWalkPerSubSample) {
  MirrorScene m(0.0f);
  TracerSettings every = test::smallGrid();
  every.evaluation.walk_edges_only = false;
  TracerSettings edges = test::smallGrid();  // aa 4, edges only: the default
  FrameRenderer a(m.scene, m.ibl, every), b(m.scene, m.ibl, edges);
  const ViewImages va = a.render(m.wall, {m.camera}, {m.view}).views.at(0);
  const ViewImages vb = b.render(m.wall, {m.camera}, {m.view}).views.at(0);
  expectFiniteAndBounded(vb);
  // The same image (the wall's edge pixels walk each sub-sample in both) from far fewer walks.
  double diff = 0.0;
  for (int y = 0; y < va.hdr.rows; ++y)
    for (int x = 0; x < va.hdr.cols; ++x) diff += glm::length(rgbAt(va.hdr, x, y) - rgbAt(vb.hdr, x, y));
  EXPECT_LT(diff / double(va.hdr.total()), 2e-3);
  EXPECT_LT(double(vb.walked_rays), 0.6 * double(va.walked_rays));
  EXPECT_GT(vb.foreground_hits, 0u);
}

TEST(FrameRenderer, TheRoughestMaterialsReadTheVisitorsPrefilteredAroundTheRelic) {
  MirrorScene m(0.6f);
  TracerSettings map = test::smallGrid();
  map.aa_samples = 1;
  TracerSettings walk = map;
  walk.foreground_map_roughness = 2.0f;
  FrameRenderer a(m.scene, m.ibl, map), b(m.scene, m.ibl, walk);
  const FrameResult with = a.render(m.wall, {m.camera}, {m.view});
  const FrameResult without = b.render(m.wall, {m.camera}, {m.view});
  ASSERT_TRUE(with.plan.has(Pass::RoughForegroundMap)) << with.plan.describe();
  ASSERT_FALSE(without.plan.has(Pass::RoughForegroundMap)) << without.plan.describe();
  expectFiniteAndBounded(with.views.at(0));
  // The red wall faces the sphere's centre: it is seen there, in its colour.
  EXPECT_GT(with.views.at(0).weight.at<float>(24, 24), 0.2f);
  const vec3 centre = rgbAt(with.views.at(0).hdr, 24, 24);
  EXPECT_GT(centre.r, 2.0f * centre.g);
  // The lobe spreads it smoothly where the walk's hit-or-miss leaves a step.
  const auto largestStep = [](const ViewImages& v) {
    float step = 0.0f;
    for (int y = 1; y < v.weight.rows; ++y)
      for (int x = 1; x < v.weight.cols; ++x)
        if (v.coverage.at<float>(y, x) == 1.0f && v.coverage.at<float>(y - 1, x - 1) == 1.0f)
          step = std::max({step, std::abs(v.weight.at<float>(y, x) - v.weight.at<float>(y - 1, x)),
                           std::abs(v.weight.at<float>(y, x) - v.weight.at<float>(y, x - 1))});
    return step;
  };
  EXPECT_LT(largestStep(with.views.at(0)), 0.1f);
  EXPECT_GT(largestStep(without.views.at(0)), 2.0f * largestStep(with.views.at(0)));
}

TEST(FrameRenderer, RoughLobesThatMissTheVoxelsStillReadTheirHalo) {
  for (float roughness : {0.1f, 0.5f}) {
    MirrorScene m(roughness);
    // The camera's mask covers the wall only, so a blurred read beside it is partial.
    m.camera.mask = cv::Mat(64, 64, CV_32FC1, cv::Scalar(0));
    for (const auto& p : m.wall.points) m.camera.mask.at<float>(p.y, p.x) = 1.0f;
    TracerSettings on = test::smallGrid();
    on.aa_samples = 1;
    on.foreground_map_roughness = 2.0f;  // the walk for every roughness
    TracerSettings off = on;
    off.lobe_fallback_roughness = 2.0f;
    FrameRenderer a(m.scene, m.ibl, on), b(m.scene, m.ibl, off);
    const ViewImages with = a.render(m.wall, {m.camera}, {m.view}).views.at(0);
    const ViewImages without = b.render(m.wall, {m.camera}, {m.view}).views.at(0);
    expectFiniteAndBounded(with);
    int more = 0, changed_hits = 0;
    for (int y = 0; y < with.weight.rows; ++y)
      for (int x = 0; x < with.weight.cols; ++x) {
        const float w1 = with.weight.at<float>(y, x), w0 = without.weight.at<float>(y, x);
        if (w0 > 0.0f && w1 != w0) ++changed_hits;  // a ray that met a voxel reads as before
        if (w0 == 0.0f && w1 > 0.0f) ++more;
      }
    EXPECT_EQ(changed_hits, 0) << roughness;
    if (roughness < on.lobe_fallback_roughness)
      EXPECT_EQ(more, 0) << "below the fallback's roughness nothing changes";
    else
      EXPECT_GT(more, 0) << "the rough sphere's rim rays pass beside the wall and read its halo";
  }
}

TEST(FrameRenderer, FullGridStaysBounded) {
  MirrorScene m(0.2f);
  TracerSettings s;
  s.grid.bounds = {vec3(-0.5f, 0.0f, -0.5f), vec3(0.5f, 1.0f, 0.5f)};
  s.grid.voxel_size = 0.05f;  // 20^3, every voxel filled (the relic sits inside the foreground)
  s.aa_samples = 1;
  ForegroundCloud full;
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 20; ++x) {
        ForegroundPoint p;
        p.position = vec3(-0.5f, 0.0f, -0.5f) + (vec3(x, y, z) + 0.5f) * 0.05f;
        full.points.push_back(p);
      }
  FrameRenderer renderer(m.scene, m.ibl, s);
  const FrameResult r = renderer.render(full, {m.camera}, {m.view});
  EXPECT_EQ(renderer.grid().occupiedCount(), 8000u);
  expectFiniteAndBounded(r.views.at(0));
  EXPECT_EQ(r.views.at(0).foreground_hits, r.views.at(0).walked_rays);
}

TEST(FrameRenderer, RejectsBadSettings) {
  MirrorScene m(0.0f);
  TracerSettings s;
  s.aa_samples = 3;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.pyramid_levels = 0;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.max_reflection_distance = kNan;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.grid.voxel_size = -1.0f;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.walk_per_pixel_roughness = kNan;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.lobe_fallback_roughness = -0.1f;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  s = TracerSettings{};
  s.evaluation.level_bias = kInf;
  EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError);
  for (int odd_or_out_of_range : {0, 3, 10}) {
    s = TracerSettings{};
    s.rough_interreflection_grid = odd_or_out_of_range;
    EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError) << odd_or_out_of_range;
  }
  for (float contrast : {-1.0f, 0.5f, kNan, kInf}) {
    s = TracerSettings{};
    s.refraction_supersample_contrast = contrast;
    EXPECT_THROW(FrameRenderer(m.scene, m.ibl, s), InputError) << contrast;
  }
  for (float contrast : {0.0f, 1.0f, 32.0f}) {
    s = TracerSettings{};
    s.refraction_supersample_contrast = contrast;
    EXPECT_NO_THROW(FrameRenderer(m.scene, m.ibl, s)) << contrast;
  }
}

}  // namespace
}  // namespace holo::reflect
