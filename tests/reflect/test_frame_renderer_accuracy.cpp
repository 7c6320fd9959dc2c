// The frame renderer's interreflection bounce: a mirror ray that meets the relic itself reflects
// what the relic reflects at that second point (the static hall and the visitors); a rough one
// samples its lobe, checked against path-traced truth.
#include <gtest/gtest.h>

#include <cstdio>

#include "holo/core/image.hpp"
#include "holo/reference/image_metrics.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;
using reference::mse;
using reference::PathTracer;
using reference::renderPathTraced;

// Two metal spheres side by side, seen from +z: the left one bright (F0 0.9), the right one dark
// (F0 0.2), under a uniform sky. The left sphere's right limb mirrors the dark sphere.
struct TwoSpheres {
  explicit TwoSpheres(float bright_roughness = 0.0f)
      : scene(model(bright_roughness), {}), ibl(sky, PrefilterOptions{5, 16, 16}) {}
  static Model model(float bright_roughness) {
    Model m = holo::test::sphereModel({vec3(0.9f), 1.0f, bright_roughness, 1.0f}, 0.15f,
                                      vec3(-0.16f, 0.3f, 0.0f), 24, 48);
    const Model dark =
        holo::test::sphereModel({vec3(0.2f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.16f, 0.3f, 0.0f), 24, 48);
    m.meshes.push_back(dark.meshes.front());
    m.meshes.back().material = 1;
    m.materials.push_back(dark.materials.front());
    return m;
  }
  const Environment sky = Environment::uniform(vec3(0.5f));
  RenderScene scene;
  PrefilteredIbl ibl;
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.5f), vec3(0.0f, 0.3f, 0.0f), 30.0f, 64, 64);
};

TEST(FrameRenderer, InterreflectionShowsWhatTheRelicMirrors) {
  TwoSpheres t;
  TracerSettings on = test::smallGrid(), off = test::smallGrid();
  off.relic_interreflection = false;
  FrameRenderer a(t.scene, t.ibl, on), b(t.scene, t.ibl, off);
  const ViewImages with = a.render(ForegroundCloud{}, {}, {t.view}).views.at(0);
  const ViewImages without = b.render(ForegroundCloud{}, {}, {t.view}).views.at(0);
  // Without the bounce every fully covered pixel of the bright sphere is the sky times its F0
  // (~0.45); with it, the pixels whose mirror ray meets the dark sphere show the dark sphere's
  // reflection of the sky (~0.9 * 0.2 * 0.5 = 0.09).
  int bright = 0, mirrored = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 32; ++x) {
      if (with.coverage.at<float>(y, x) < 1.0f) continue;
      const float g0 = rgbAt(without.hdr, x, y).g, g1 = rgbAt(with.hdr, x, y).g;
      ASSERT_TRUE(std::isfinite(g1));
      EXPECT_NEAR(g0, 0.45f, 0.06f) << x << "," << y;
      if (g1 < 0.15f) ++mirrored;
      if (std::abs(g1 - g0) < 1e-4f) ++bright;
    }
  EXPECT_GT(mirrored, 3) << "the bright sphere mirrors the dark one at its right limb";
  EXPECT_GT(bright, 10 * mirrored) << "elsewhere the bounce changes nothing";

  // The foreground through the bounce: a red wall in front (visible in the dark sphere's mirror
  // image of the bright one's limb, and directly). The bright sphere shows more of it with the
  // bounce, and never less.
  const holo::test::RedWall wall = holo::test::redWall();
  const ViewImages fg_on = a.render(wall.cloud, {wall.camera}, {t.view}).views.at(0);
  const ViewImages fg_off = b.render(wall.cloud, {wall.camera}, {t.view}).views.at(0);
  int more = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 32; ++x) {
      if (with.coverage.at<float>(y, x) < 1.0f) continue;
      const float w1 = fg_on.weight.at<float>(y, x), w0 = fg_off.weight.at<float>(y, x);
      ASSERT_GE(w1, 0.0f);
      ASSERT_LE(w1, 1.0f);
      if (w1 > w0 + 0.5f) ++more;
    }
  EXPECT_GT(more, 0);
}

TEST(FrameRenderer, RoughInterreflectionFollowsThePathTracedLobe) {
  // The bright sphere rough (0.6, read from the rough foreground map): near its right limb part of
  // its lobe meets the dark sphere. Error over the bright sphere against path-traced truth: the
  // mirror ray, the interleaved 4x4 lobe strata (1 ray per sample) and every sample tracing all 16.
  TwoSpheres t(0.6f);
  const PathTracer tracer(t.scene, t.sky);
  const cv::Mat truth = renderPathTraced(tracer, t.view, 256);
  const auto error = [&](int grid, bool interleaved, int aa_samples = 4, bool jittered = true) {
    TracerSettings s = test::smallGrid();
    s.evaluation.lobe_strata_jittered = jittered;
    s.aa_samples = aa_samples;
    s.rough_interreflection_grid = grid;
    s.evaluation.rough_interreflection_interleaved = interleaved;
    FrameRenderer renderer(t.scene, t.ibl, s);
    const ViewImages v = renderer.render(ForegroundCloud{}, {}, {t.view}).views.at(0);
    // The bright sphere's inside, a pixel from its silhouette (whose aliasing differs with the
    // samples per pixel).
    cv::Mat bright(64, 64, CV_8UC1, cv::Scalar(0));
    for (int y = 1; y < 63; ++y)
      for (int x = 1; x < 32; ++x) {
        EXPECT_TRUE(isFinite(rgbAt(v.hdr, x, y))) << x << "," << y;
        bool inside = true;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) inside = inside && v.coverage.at<float>(y + dy, x + dx) == 1.0f;
        if (inside) bright.at<std::uint8_t>(y, x) = 255;
      }
    EXPECT_GT(cv::countNonZero(bright), 200);
    return mse(v.hdr, truth, bright);
  };
  const double mirror = error(1, true), interleaved = error(4, true), full = error(4, false);
  // One sample per pixel: each traces its class's four strata.
  const double mirror_aa1 = error(1, true, 1), interleaved_aa1 = error(4, true, 1);
  // At the strata's centres both trace the same directions (the same quadrature).
  const double centres_interleaved = error(4, true, 4, false), centres_full = error(4, false, 4, false);
  std::printf(
      "mse against path-traced truth: mirror %.3g, interleaved 4x4 %.3g, all 16 per sample %.3g; one "
      "sample per pixel: mirror %.3g, interleaved %.3g; at the strata's centres: interleaved %.3g, all "
      "16 %.3g\n",
      mirror, interleaved, full, mirror_aa1, interleaved_aa1, centres_interleaved, centres_full);
  // The mirror ray is all or nothing; the lobe's share of the dark sphere grades it, and the
  // interleaved strata come close to tracing all of them at a sixteenth of the rays (held at the
  // centres; at the default sequence points the interleaved error, 4.0e-5, is below the centres'
  // 5.4e-5, and all 16 per sample, averaging four points a stratum, lower still).
  EXPECT_LT(full, 0.25 * mirror);
  EXPECT_LT(interleaved, 0.25 * mirror);
  EXPECT_LT(centres_interleaved, 1.2 * centres_full);
  EXPECT_LT(interleaved_aa1, 0.25 * mirror_aa1);
}

TEST(FrameRenderer, ARetracedRoughLobeIsTheOneAFreshRendererTraces) {
  // A view keeps its pixels' rough-lobe sums from one static pass to the next and resets only the
  // pixels the last pass marked rough: traced again from an eye beside the first, the image must
  // be bit for bit a fresh renderer's, with nothing of the first eye's lobes pooled into it.
  TwoSpheres t(0.6f);
  const TracerSettings s = test::smallGrid();
  const CameraModel beside = lookAtCamera(vec3(0.03f, 0.32f, 1.5f), vec3(0.0f, 0.3f, 0.0f), 30.0f, 64, 64);
  FrameRenderer renderer(t.scene, t.ibl, s);
  const ViewImages first = renderer.render(ForegroundCloud{}, {}, {t.view}).views.at(0);
  EXPECT_GT(first.interreflected_samples, 0u);
  const ViewImages again = renderer.render(ForegroundCloud{}, {}, {beside}).views.at(0);
  EXPECT_FALSE(again.static_reused);
  FrameRenderer fresh(t.scene, t.ibl, s);
  const ViewImages alone = fresh.render(ForegroundCloud{}, {}, {beside}).views.at(0);
  EXPECT_GT(alone.interreflected_samples, 0u);
  EXPECT_EQ(cv::norm(again.hdr, alone.hdr, cv::NORM_INF), 0.0);
  // And back: the first eye again gives the first image.
  const ViewImages back = renderer.render(ForegroundCloud{}, {}, {t.view}).views.at(0);
  EXPECT_EQ(cv::norm(back.hdr, first.hdr, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace holo::reflect
