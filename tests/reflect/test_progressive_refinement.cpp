// Progressive refinement while nothing moves (ProgressiveRefinement, reflect/src/
// progressive_accumulation.hpp) on the rough metal bowl, whose inside reflects a blur of itself
// through the rough interreflection's strata: a still view's error against the converged image
// falls monotonically below 10% of the interreflected light within the frames 2 s give at the
// live rate; a visitor stepping in resets the view to set 0 in that frame; switched off, the error
// stays; a relic without a rough lobe does none of the work. Frames are counted, never timed.
// The full-size curve: `holopyramid eval refinement` (docs/reflect.md, progressive refinement).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/image.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "progressive_accumulation.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reflect {
namespace {

// The frames 2 s hold at the metal bowl's refining frame measured at 320^2 (4.99 fps, four views;
// docs/tracer/progressive_refinement.md), and at the live loop's measured rate (30 fps,
// docs/frame_loop.md), the length of the curve.
constexpr int kFramesInTwoSecondsMeasured = 9;
constexpr int kFramesInTwoSeconds = 60;
// The converged image: this many sample sets.
constexpr int kConvergedSets = 256;
constexpr int kSize = 40;

// A sky over a darker ground with a bright warm window low on one side.
cv::Mat skyPanorama() {
  cv::Mat pano(32, 64, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const float v = (float(y) + 0.5f) / float(pano.rows);
      vec3 rgb = v < 0.5f ? vec3(0.6f, 0.8f, 1.2f) * (1.2f - v) : vec3(0.25f, 0.2f, 0.15f);
      if (v > 0.3f && v < 0.5f && x < pano.cols / 8) rgb = vec3(6.0f, 4.0f, 2.5f);
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(rgb.z, rgb.y, rgb.x);
    }
  return pano;
}

// Looking into the bowl, 55 degrees above the horizon.
CameraModel bowlView(const Bounds3& b, float azimuth = 0.0f) {
  const vec3 target(0.0f, 0.45f * b.hi.y, 0.0f);
  const float up = glm::radians(55.0f);
  const vec3 eye =
      target + 0.75f * vec3(std::cos(up) * std::sin(azimuth), std::sin(up), std::cos(up) * std::cos(azimuth));
  return lookAtCamera(eye, target, framingFovDeg(eye, b), kSize, kSize);
}

struct Bowl {
  Bowl()
      : scene(relics::makeRelic("metal-bowl"), {}),
        ibl(Environment(skyPanorama()), PrefilterOptions{6, 32, 16}) {}
  RenderScene scene;
  PrefilteredIbl ibl;
};

TracerSettings settings(int sets) {
  TracerSettings s;
  s.refinement_sets = sets;
  return s;
}

// Luminance RMS of a - b over the pixels where `region` is set.
double rmsDifference(const cv::Mat& a, const cv::Mat& b, const cv::Mat& region) {
  double sq = 0;
  int n = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x)
      if (region.at<std::uint8_t>(y, x)) {
        const double d = luminance(rgbAt(a, x, y)) - luminance(rgbAt(b, x, y));
        sq += d * d;
        ++n;
      }
  return n ? std::sqrt(sq / n) : 0.0;
}

// The converged image, the same without interreflection, and where the interreflected light shows.
struct Reference {
  cv::Mat converged, region;
  double interreflected = 0;  // its luminance RMS over the region
};

Reference reference(const Bowl& b, const CameraModel& view) {
  Reference r;
  FrameRenderer converging(b.scene, b.ibl, settings(kConvergedSets));
  for (int f = 0; f < kConvergedSets; ++f) r.converged = converging.render({}, {}, {view}).views.at(0).hdr;
  TracerSettings none;
  none.relic_interreflection = false;
  const cv::Mat without = FrameRenderer(b.scene, b.ibl, none).render({}, {}, {view}).views.at(0).hdr;
  r.region = cv::Mat(view.height(), view.width(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x)
      if (std::abs(luminance(rgbAt(r.converged, x, y)) - luminance(rgbAt(without, x, y))) > 1e-3)
        r.region.at<std::uint8_t>(y, x) = 1;
  r.interreflected = rmsDifference(r.converged, without, r.region);
  return r;
}

TEST(ProgressiveRefinement, StillViewConvergesMonotonicallyWithinTwoSecondsOfFrames) {
  const Bowl b;
  const CameraModel view = bowlView(b.scene.relicBounds());
  const Reference ref = reference(b, view);
  ASSERT_GT(cv::countNonZero(ref.region), 300);
  FrameRenderer renderer(b.scene, b.ibl);
  std::vector<double> error;
  for (int f = 0; f < kFramesInTwoSeconds; ++f) {
    const FrameResult r = renderer.render({}, {}, {view});
    ASSERT_TRUE(r.plan.has(Pass::ProgressiveRefinement)) << r.plan.describe();
    EXPECT_EQ(r.views.at(0).accumulated_sets, std::uint32_t(f + 1));
    if (f > 0) {
      EXPECT_GT(r.views.at(0).refinement_samples, 0u);
    }
    error.push_back(rmsDifference(r.views.at(0).hdr, ref.converged, ref.region) / ref.interreflected);
  }
  std::printf("error / interreflected light, frames 1..%d:", kFramesInTwoSeconds);
  for (double e : error) std::printf(" %.4f", e);
  std::printf("\n");
  // Monotonic within the sampling's own noise at this size: a frame never rises more than 18%
  // above the best error so far (16.8% measured, set 0 the first point of each sample's sequence), and
  // every 8 frames the error is lower (strictly frame by frame, a few hundred pixels' errors rise by
  // a few percent now and then; docs/reflect.md has the full-size curve). Down to 1% only: below it
  // the comparison measures the converged image's own error (the curve levels off at about 0.6%
  // from frame 43 on).
  double best = error.front(), worst_rise = 0;
  for (std::size_t f = 1; f < error.size() && error[f - 1] > 0.01; ++f) {
    worst_rise = std::max(worst_rise, error[f] / best - 1.0);
    EXPECT_LE(error[f], 1.18 * best) << "frame " << f + 1;
    best = std::min(best, error[f]);
    if (f >= 8) {
      EXPECT_LT(error[f], error[f - 8]) << "frame " << f + 1;
    }
  }
  std::printf("largest rise over the best so far: %.1f%%\n", 100.0 * worst_rise);
  EXPECT_GT(error.front(), 0.10);  // one set alone is not converged: a bar that could fail
  EXPECT_LT(error[kFramesInTwoSecondsMeasured - 1], 0.10);
  EXPECT_LT(error.back(), 0.10);
  EXPECT_LT(error.back(), 0.2 * error.front());

  // Switched off: every frame shows set 0, the error stays where it started.
  FrameRenderer off(b.scene, b.ibl, settings(1));
  FrameResult last;
  for (int f = 0; f < kFramesInTwoSeconds; ++f) last = off.render({}, {}, {view});
  EXPECT_FALSE(last.plan.has(Pass::ProgressiveRefinement)) << last.plan.describe();
  const double off_error =
      rmsDifference(last.views.at(0).hdr, ref.converged, ref.region) / ref.interreflected;
  EXPECT_NEAR(off_error, error.front(), 1e-6);
  EXPECT_GT(off_error, 3.0 * error.back());
}

TEST(ProgressiveRefinement, VisitorSteppingInOrEyeMovingResetsInThatFrame) {
  const Bowl b;
  const CameraModel view = bowlView(b.scene.relicBounds());
  const holo::test::RedWall visitor = holo::test::redWall(-0.2f, 0.1f, 41, 41);
  FrameRenderer renderer(b.scene, b.ibl);
  const cv::Mat first = renderer.render({}, {}, {view}).views.at(0).hdr.clone();
  for (int f = 1; f < 8; ++f) renderer.render({}, {}, {view});
  const FrameResult still = renderer.render({}, {}, {view});
  EXPECT_EQ(still.views.at(0).accumulated_sets, 9u);
  ASSERT_GT(cv::norm(still.views.at(0).hdr, first, cv::NORM_INF), 1e-3);

  // The visitor steps in: this very frame shows set 0 again, outside the pixels the visitor's
  // reflection reaches exactly the first frame's image.
  const FrameResult in = renderer.render(visitor.cloud, {visitor.camera}, {view});
  ASSERT_TRUE(in.plan.has(Pass::VoxelGrid)) << in.plan.describe();
  const ViewImages& v = in.views.at(0);
  EXPECT_TRUE(v.refinement_reset);
  EXPECT_EQ(v.accumulated_sets, 1u);
  cv::Mat unreached;
  cv::compare(v.weight, 0.0f, unreached, cv::CMP_EQ);
  ASSERT_GT(cv::countNonZero(unreached), kSize * kSize / 2);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (unreached.at<std::uint8_t>(y, x)) {
        ASSERT_EQ(rgbAt(v.hdr, x, y), rgbAt(first, x, y)) << x << "," << y;
      }

  // The visitor stands still: the view refines again from the next frame on.
  const FrameResult standing = renderer.render(visitor.cloud, {visitor.camera}, {view});
  EXPECT_FALSE(standing.views.at(0).refinement_reset);
  EXPECT_EQ(standing.views.at(0).accumulated_sets, 2u);

  // The eye moves: the view is traced again at set 0.
  const FrameResult moved =
      renderer.render(visitor.cloud, {visitor.camera}, {bowlView(b.scene.relicBounds(), 0.3f)});
  EXPECT_FALSE(moved.views.at(0).static_reused);
  EXPECT_EQ(moved.views.at(0).accumulated_sets, 1u);
  EXPECT_EQ(moved.views.at(0).refinement_samples, 0u);
}

TEST(ProgressiveRefinement, ConvergedOrSmoothRelicsDoNoneOfTheWork) {
  const Bowl b;
  const CameraModel view = bowlView(b.scene.relicBounds());
  FrameRenderer renderer(b.scene, b.ibl, settings(4));
  std::vector<std::uint64_t> samples;
  for (int f = 0; f < 6; ++f)
    samples.push_back(renderer.render({}, {}, {view}).views.at(0).refinement_samples);
  EXPECT_EQ(samples[0], 0u);  // the static pass shaded set 0
  EXPECT_GT(samples[1], 0u);
  EXPECT_EQ(samples[3], samples[1]);
  EXPECT_EQ(samples[4], 0u);  // four sets: converged as far as it goes, no work
  EXPECT_EQ(samples[5], 0u);

  // A mirror-smooth sphere traces no lobe: no plan entry, no work.
  const RenderScene sphere(relics::makeRelic("sphere"), {});
  FrameRenderer smooth(sphere, b.ibl);
  for (int f = 0; f < 3; ++f) {
    const FrameResult r = smooth.render({}, {}, {bowlView(sphere.relicBounds())});
    EXPECT_FALSE(r.plan.has(Pass::ProgressiveRefinement)) << r.plan.describe();
    EXPECT_EQ(r.views.at(0).refinement_samples, 0u);
    EXPECT_EQ(r.views.at(0).accumulated_sets, 0u);
  }
}

// "Still" for the visitors: the signature follows what the grid holds, not the order the points
// came in.
TEST(ProgressiveRefinement, ForegroundSignatureFollowsWhatTheGridHolds) {
  depthfilter::ForegroundCloud cloud = holo::test::redWall(-0.2f, 0.1f, 21, 21).cloud;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) cloud.points[i].weight = 0.5f + 0.001f * float(i);
  depthfilter::ForegroundCloud reversed = cloud, moved = cloud;
  std::reverse(reversed.points.begin(), reversed.points.end());
  moved.points[0].position.z += 0.1f;
  VoxelGrid a, b, c, empty;
  a.build(cloud);
  b.build(reversed);
  c.build(moved);
  EXPECT_EQ(foregroundSignature(a), foregroundSignature(b));
  EXPECT_NE(foregroundSignature(a), foregroundSignature(c));
  EXPECT_NE(foregroundSignature(a), foregroundSignature(empty));
}

}  // namespace
}  // namespace holo::reflect
