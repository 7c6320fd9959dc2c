// The frame renderer's accuracy additions: the relic's interreflection bounce (a mirror ray that
// meets the relic itself reflects what the second point reflects) and the supersampling of the
// reflected foreground's edges (stratifiedPattern, traceSamples).
#include <gtest/gtest.h>

#include <limits>
#include <set>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

TracerSettings smallGrid() {
  TracerSettings s;
  s.grid.bounds = {vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.5f, 1.0f)};
  s.grid.voxel_size = 0.02f;
  return s;
}

// A wall of red foreground points at z = 0.6 between the relic and the viewer, x in [x0, x1],
// y in [-0.1, 0.7], seen by one camera behind the relic.
struct RedWall {
  explicit RedWall(float x0 = -0.4f, float x1 = 0.4f) {
    camera.camera = lookAtCamera(vec3(0.0f, 0.3f, -0.2f), vec3(0.0f, 0.3f, 0.6f), 100.0f, 64, 64);
    camera.colour_bgr = cv::Mat(64, 64, CV_32FC3, cv::Scalar(0, 0, 2));  // red, linear
    camera.mask = cv::Mat(64, 64, CV_32FC1, cv::Scalar(1));
    for (float x = x0; x <= x1 + 1e-4f; x += 0.01f)
      for (float y = -0.1f; y <= 0.7f + 1e-4f; y += 0.01f) {
        ForegroundPoint p;
        p.position = vec3(x, y, 0.6f);
        p.radiance = vec3(2.0f, 0.0f, 0.0f);
        const auto px = camera.camera.project(p.position);
        p.x = std::uint16_t(std::clamp(px ? px->x : 0.0f, 0.0f, 63.0f));
        p.y = std::uint16_t(std::clamp(px ? px->y : 0.0f, 0.0f, 63.0f));
        cloud.points.push_back(p);
      }
  }
  ForegroundCameraImage camera;
  ForegroundCloud cloud;
};

TEST(StratifiedPattern, OnePointPerCellWithDistinctCoordinates) {
  for (int n : {1, 2, 3, 4, 8, 16}) {
    const std::vector<vec2> pattern = stratifiedPattern(n * n);
    ASSERT_EQ(pattern.size(), std::size_t(n * n));
    std::set<float> xs, ys;
    std::set<std::pair<int, int>> cells;
    vec2 mean(0.0f);
    for (const vec2& o : pattern) {
      ASSERT_GT(o.x, -0.5f);
      ASSERT_LT(o.x, 0.5f);
      ASSERT_GT(o.y, -0.5f);
      ASSERT_LT(o.y, 0.5f);
      xs.insert(o.x);
      ys.insert(o.y);
      cells.insert({int(std::floor((o.x + 0.5f) * float(n))), int(std::floor((o.y + 0.5f) * float(n)))});
      mean += o;
    }
    EXPECT_EQ(xs.size(), pattern.size()) << n;
    EXPECT_EQ(ys.size(), pattern.size()) << n;
    EXPECT_EQ(cells.size(), pattern.size()) << "one sample per cell of the " << n << "x" << n << " grid";
    EXPECT_NEAR(mean.x / float(n * n), 0.0f, 1e-5f);
    EXPECT_NEAR(mean.y / float(n * n), 0.0f, 1e-5f);
    EXPECT_EQ(pattern, stratifiedPattern(n * n)) << "deterministic";
  }
  for (int bad : {0, -4, 2, 5, 17 * 17}) EXPECT_THROW(stratifiedPattern(bad), InputError) << bad;
}

TEST(TraceSamples, MatchesTheHitPointsOfTheSameRays) {
  const RenderScene scene(
      holo::test::sphereModel({vec3(0.9f), 1.0f, 0.1f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f)), {});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 40, 40);
  HitPointBuffer full;
  traceHitPoints(scene, view, AntiAliasing::Full, full);
  // Every fifth pixel of the image (some on the sphere, some beside it) with the four-sample
  // pattern: the same hits as the Full anti-aliasing pass.
  std::vector<std::uint32_t> pixels;
  for (std::uint32_t p = 0; p < 40 * 40; p += 5) pixels.push_back(p);
  const std::vector<vec2> pattern = subsamplePattern(4);
  std::vector<HitPoint> hits;
  std::vector<std::uint8_t> valid;
  traceSamples(scene, view, pixels, pattern, hits, valid);
  ASSERT_EQ(hits.size(), pixels.size() * 4);
  int both = 0;
  for (std::size_t k = 0; k < pixels.size(); ++k)
    for (std::size_t s = 0; s < 4; ++s) {
      const std::size_t ref = full.firstSample(pixels[k]) + s;
      const std::size_t i = k * 4 + s;
      ASSERT_EQ(valid[i], full.valid[ref]) << pixels[k] << " sample " << s;
      if (!valid[i]) continue;
      ++both;
      EXPECT_LT(glm::distance(hits[i].position, full.hits[ref].position), 1e-6f);
      EXPECT_LT(glm::distance(hits[i].reflected, full.hits[ref].reflected), 1e-6f);
    }
  EXPECT_GT(both, 100);
  traceSamples(scene, view, {}, pattern, hits, valid);
  EXPECT_TRUE(hits.empty());
}

// Two metal spheres side by side, seen from +z: the left one bright (F0 0.9), the right one dark
// (F0 0.2), under a uniform sky. The left sphere's right limb mirrors the dark sphere.
struct TwoSpheres {
  TwoSpheres() : scene(model(), {}), ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16}) {}
  static Model model() {
    Model m =
        holo::test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(-0.16f, 0.3f, 0.0f), 24, 48);
    const Model dark =
        holo::test::sphereModel({vec3(0.2f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.16f, 0.3f, 0.0f), 24, 48);
    m.meshes.push_back(dark.meshes.front());
    m.meshes.back().material = 1;
    m.materials.push_back(dark.materials.front());
    return m;
  }
  RenderScene scene;
  PrefilteredIbl ibl;
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.5f), vec3(0.0f, 0.3f, 0.0f), 30.0f, 64, 64);
};

TEST(FrameRenderer, InterreflectionShowsWhatTheRelicMirrors) {
  TwoSpheres t;
  TracerSettings on = smallGrid(), off = smallGrid();
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
  const RedWall wall;
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

TEST(FrameRenderer, EdgeSupersamplingApproachesAManySampleReference) {
  // A mirror sphere reflecting a wall with vertical edges (x in [-0.15, 0.15]).
  const RenderScene scene(
      holo::test::sphereModel({vec3(0.9f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 48, 96), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16});
  const RedWall wall(-0.15f, 0.15f);
  const int size = 40, scale = 4;
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, size, size);
  const CameraModel fine =
      lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, size * scale, size * scale);
  TracerSettings plain = smallGrid(), super = smallGrid();
  plain.edge_samples = 0;
  super.edge_samples = 16;
  FrameRenderer a(scene, ibl, plain), b(scene, ibl, super), c(scene, ibl, plain);
  const ViewImages v0 = a.render(wall.cloud, {wall.camera}, {view}).views.at(0);
  const ViewImages v1 = b.render(wall.cloud, {wall.camera}, {view}).views.at(0);
  // Reference: 4 sub-samples in each of 4x4 finer pixels, i.e. 64 per pixel.
  const ViewImages ref_fine = c.render(wall.cloud, {wall.camera}, {fine}).views.at(0);
  cv::Mat ref;
  cv::resize(ref_fine.hdr, ref, cv::Size(size, size), 0, 0, cv::INTER_AREA);

  EXPECT_EQ(v0.supersampled_pixels, 0u);
  const int relic = cv::countNonZero(v1.coverage);
  EXPECT_GT(v1.supersampled_pixels, 0u);
  EXPECT_LT(double(v1.supersampled_pixels), 0.25 * relic) << "only the few pixels an edge crosses";
  double err0 = 0.0, err1 = 0.0;
  std::size_t changed = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const vec3 c0 = rgbAt(v0.hdr, x, y), c1 = rgbAt(v1.hdr, x, y), r = rgbAt(ref, x, y);
      ASSERT_TRUE(isFinite(c1));
      ASSERT_GE(glm::min(c1.x, glm::min(c1.y, c1.z)), 0.0f);
      if (glm::length(c1 - c0) < 1e-6f) continue;
      ++changed;
      err0 += double(glm::length(c0 - r));
      err1 += double(glm::length(c1 - r));
    }
  EXPECT_GT(changed, 0u);
  EXPECT_LE(changed, v1.supersampled_pixels);
  EXPECT_LT(err1, 0.5 * err0) << "supersampled pixels are nearer the 64-sample reference";
}

TEST(FrameRenderer, RejectsBadEdgeSamples) {
  TwoSpheres t;
  for (int bad : {1, 3, 8, -9, 17 * 17}) {
    TracerSettings s;
    s.edge_samples = bad;
    EXPECT_THROW(FrameRenderer(t.scene, t.ibl, s), InputError) << bad;
  }
  TracerSettings off;
  off.edge_samples = 0;
  EXPECT_NO_THROW(FrameRenderer(t.scene, t.ibl, off));
}

}  // namespace
}  // namespace holo::reflect
