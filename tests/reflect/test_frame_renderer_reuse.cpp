// The frame renderer's savings for the live loop: edge anti-aliasing (four sub-samples only where
// a pixel's centre differs from a neighbour's) against four everywhere, and the per-view cache of
// hit points and static shading against rendering from scratch, and its budget of views traced
// again per frame (static_pass_schedule.hpp).
#include <gtest/gtest.h>

#include <vector>

#include <opencv2/core.hpp>

#include <tbb/task_arena.h>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"
#include "static_pass_schedule.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

// A glossy sphere under a sky that varies with direction (so the reflection has structure to
// alias), a small test::redWall() between it and the viewer, one camera that sees the wall.
struct SphereScene {
  SphereScene()
      : scene(holo::test::sphereModel({vec3(0.9f), 1.0f, 0.1f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 24, 48),
              {}),
        ibl(Environment(gradientSky()), PrefilterOptions{5, 16, 16}) {
    const holo::test::RedWall red = holo::test::redWall(-0.2f, 0.1f, 41, 41);
    camera = red.camera;
    wall = red.cloud;
  }
  static cv::Mat gradientSky() {
    cv::Mat sky(32, 64, CV_32FC3);
    for (int y = 0; y < sky.rows; ++y)
      for (int x = 0; x < sky.cols; ++x)
        sky.at<cv::Vec3f>(y, x) = cv::Vec3f(0.1f + 0.02f * float(x % 16), 0.2f + 0.03f * float(y), 0.5f);
    return sky;
  }
  CameraModel view(const vec3& eye, int size = 64) const {
    return lookAtCamera(eye, vec3(0.0f, 0.3f, 0.0f), 16.0f, size, size);
  }
  RenderScene scene;
  PrefilteredIbl ibl;
  ForegroundCameraImage camera;
  ForegroundCloud wall;
};

TracerSettings settings(int samples, bool edges, float reuse = 0.0f) {
  TracerSettings s;
  s.grid.bounds = {vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.5f, 1.0f)};
  s.grid.voxel_size = 0.02f;
  s.aa_samples = samples;
  s.edge_aa = edges;
  s.static_reuse_distance = reuse;
  s.exposure = 1.5f;
  return s;
}

double meanAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L1) / double(a.total() * std::size_t(a.channels()));
}

bool hasPass(const ViewImages& v, Pass pass) {
  for (const PassTiming& t : v.timings)
    if (t.pass == pass) return true;
  return false;
}

const vec3 kEye(0.0f, 0.3f, 1.2f);

TEST(HitPoints, EdgeAntiAliasingRefinesEveryPartlyCoveredPixel) {
  const SphereScene s;
  const CameraModel view = s.view(kEye);
  HitPointBuffer none, edges, full;
  traceHitPoints(s.scene, view, AntiAliasing::None, none);
  traceHitPoints(s.scene, view, AntiAliasing::Edges, edges);
  traceHitPoints(s.scene, view, AntiAliasing::Full, full);
  EXPECT_TRUE(none.refined.empty());
  EXPECT_EQ(full.refined.size(), full.pixelCount());
  int partial = 0, hit = 0;
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x) {
      const std::size_t p = std::size_t(y * view.width() + x);
      const float c = full.coverage(x, y);
      hit += c > 0.0f ? 1 : 0;
      const float n = none.coverage(x, y);
      EXPECT_TRUE(n == 0.0f || n == 1.0f);
      if (c > 0.0f && c < 1.0f) {
        ++partial;
        EXPECT_EQ(edges.sampleCount(p), 4) << "silhouette pixel " << x << "," << y << " not refined";
      }
      if (edges.sampleCount(p) == 4) {
        EXPECT_EQ(edges.coverage(x, y), c) << x << "," << y;
      }
    }
  EXPECT_GT(partial, 20);
  // Refined: the silhouette ring and the sphere's facet creases, far fewer than the relic's pixels.
  EXPECT_LT(edges.refined.size(), std::size_t(hit) / 2) << edges.refined.size() << " of " << hit;
}

TEST(HitPoints, CullingToTheRelicsProjectedBoxAndTrianglesChangesNothing) {
  const SphereScene s;
  for (const vec3& eye : {kEye, vec3(0.9f, 0.9f, 0.4f), vec3(0.0f, 0.3f, 0.4f)})
    for (AntiAliasing aa : {AntiAliasing::None, AntiAliasing::Edges, AntiAliasing::Full}) {
      const CameraModel view = s.view(eye);
      HitPointBuffer all, culled;
      traceHitPoints(s.scene, view, aa, all);
      traceHitPoints(s.scene, view, aa, culled, s.scene.relicBounds());
      int hits = 0;
      for (int y = 0; y < view.height(); ++y)
        for (int x = 0; x < view.width(); ++x) {
          EXPECT_EQ(culled.coverage(x, y), all.coverage(x, y))
              << antiAliasingName(aa) << " " << x << "," << y;
          hits += all.coverage(x, y) > 0.0f ? 1 : 0;
        }
      EXPECT_GT(hits, 100);
      if (aa != AntiAliasing::Full) {
        EXPECT_EQ(culled.refined, all.refined) << antiAliasingName(aa);
      }
    }
}

TEST(FrameRenderer, EdgeAntiAliasingIsCloseToFourSamplesEverywhere) {
  const SphereScene s;
  const CameraModel view = s.view(kEye);
  auto render = [&](int samples, bool edges) {
    FrameRenderer renderer(s.scene, s.ibl, settings(samples, edges));
    return renderer.render(s.wall, {s.camera}, {view}).views.at(0).display;
  };
  const cv::Mat full = render(4, false), edges = render(1, true), none = render(1, false);
  const double e_edges = meanAbsDifference(edges, full), e_none = meanAbsDifference(none, full);
  RecordProperty("mean_abs_8bit_edges_vs_full", std::to_string(e_edges));
  RecordProperty("mean_abs_8bit_none_vs_full", std::to_string(e_none));
  EXPECT_GT(e_none, 0.05);  // one sample aliases the silhouette: a real difference to remove
  EXPECT_LT(e_edges, e_none / 3.0) << "edges " << e_edges << ", none " << e_none;
}

TEST(FrameRenderer, ReusedStaticPassesGiveExactlyTheFreshImage) {
  const SphereScene s;
  const CameraModel view = s.view(kEye);
  FrameRenderer renderer(s.scene, s.ibl, settings(1, true));
  const FrameResult first = renderer.render(ForegroundCloud{}, {s.camera}, {view});
  const cv::Mat first_hdr = first.views.at(0).hdr.clone(), first_display = first.views.at(0).display.clone();
  EXPECT_FALSE(first.views.at(0).static_reused);
  const FrameResult second = renderer.render(s.wall, {s.camera}, {view});
  const ViewImages& v = second.views.at(0);
  ASSERT_TRUE(second.plan.has(Pass::ForegroundWalk)) << second.plan.describe();
  EXPECT_TRUE(v.static_reused);
  EXPECT_FALSE(hasPass(v, Pass::HitPoints));
  EXPECT_FALSE(hasPass(v, Pass::StaticReflections));
  EXPECT_GT(v.composed_pixels, 0u);

  FrameRenderer fresh(s.scene, s.ibl, settings(1, true));
  const ViewImages f = fresh.render(s.wall, {s.camera}, {view}).views.at(0);
  EXPECT_EQ(cv::norm(v.hdr, f.hdr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(v.display, f.display, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(v.weight, f.weight, cv::NORM_INF), 0.0);
  // The fused tone map is the tone map of the composed HDR image, pixel for pixel.
  EXPECT_EQ(cv::norm(v.display, toneMap(v.hdr, v.exposure), cv::NORM_INF), 0.0);
  // The visitor is in the reflection: the second frame differs from the first where he is.
  EXPECT_GT(cv::norm(v.hdr, first_hdr, cv::NORM_INF), 0.1);
  // The first frame's images were not written over by the second.
  EXPECT_EQ(cv::norm(first.views.at(0).hdr, first_hdr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(first.views.at(0).display, first_display, cv::NORM_INF), 0.0);

  // Without foreground the cached static image is the frame, and it matches the first.
  const ViewImages third = renderer.render(ForegroundCloud{}, {s.camera}, {view}).views.at(0);
  EXPECT_TRUE(third.static_reused);
  EXPECT_EQ(cv::norm(third.hdr, first_hdr, cv::NORM_INF), 0.0);
}

TEST(FrameRenderer, ViewsRenderedTogetherAreEachViewRenderedAlone) {
  // The views of a frame are rendered in parallel: with two threads for four views, every image
  // must be bit for bit the one a renderer given that view alone draws.
  const SphereScene s;
  const std::vector<CameraModel> views = {s.view(kEye), s.view(vec3(1.2f, 0.3f, 0.0f)),
                                          s.view(vec3(0.0f, 0.5f, -1.2f)), s.view(vec3(-1.2f, 0.4f, 0.1f))};
  FrameRenderer together(s.scene, s.ibl, settings(1, true));
  FrameResult frame;
  tbb::task_arena(2).execute([&] { frame = together.render(s.wall, {s.camera}, views); });
  ASSERT_EQ(frame.views.size(), views.size());
  std::size_t composed = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    FrameRenderer alone(s.scene, s.ibl, settings(1, true));
    const ViewImages a = alone.render(s.wall, {s.camera}, {views[v]}).views.at(0);
    const ViewImages& t = frame.views[v];
    EXPECT_EQ(t.camera.position(), views[v].position()) << "view " << v;
    EXPECT_EQ(cv::norm(t.hdr, a.hdr, cv::NORM_INF), 0.0) << "view " << v;
    EXPECT_EQ(cv::norm(t.display, a.display, cv::NORM_INF), 0.0) << "view " << v;
    EXPECT_EQ(cv::norm(t.weight, a.weight, cv::NORM_INF), 0.0) << "view " << v;
    EXPECT_EQ(t.composed_pixels, a.composed_pixels) << "view " << v;
    composed += t.composed_pixels;
  }
  // The visitor is reflected in some view, so the comparison covers the foreground walk too.
  EXPECT_GT(composed, 0u);
  // The views differ: a mix-up of views or caches would show.
  EXPECT_GT(cv::norm(frame.views[0].hdr, frame.views[1].hdr, cv::NORM_INF), 0.1);
}

TEST(FrameRenderer, AMovedEyeRetracesBeyondTheReuseDistance) {
  const SphereScene s;
  FrameRenderer renderer(s.scene, s.ibl, settings(1, true, 0.01f));
  const ViewImages a = renderer.render(s.wall, {s.camera}, {s.view(kEye)}).views.at(0);
  EXPECT_FALSE(a.static_reused);
  // 5 mm: within the distance, rendered from the cached eye.
  const ViewImages b =
      renderer.render(s.wall, {s.camera}, {s.view(kEye + vec3(0.005f, 0.0f, 0.0f))}).views.at(0);
  EXPECT_TRUE(b.static_reused);
  EXPECT_EQ(b.camera.position(), kEye);
  // 5 cm: traced again from the new eye.
  const vec3 moved = kEye + vec3(0.05f, 0.0f, 0.0f);
  const ViewImages c = renderer.render(s.wall, {s.camera}, {s.view(moved)}).views.at(0);
  EXPECT_FALSE(c.static_reused);
  EXPECT_TRUE(hasPass(c, Pass::HitPoints));
  EXPECT_EQ(c.camera.position(), moved);
  // Another size is another view.
  const ViewImages d = renderer.render(s.wall, {s.camera}, {s.view(moved, 48)}).views.at(0);
  EXPECT_FALSE(d.static_reused);
  EXPECT_EQ(d.display.cols, 48);
}

TEST(FrameRenderer, ComposedImagesWrittenAgainEqualFreshOnesAndKeptOnesStay) {
  // A renderer whose caller lets each frame go before the next composes into the images it handed
  // out before (restoring the covered pixels from the static ones, or copying those whole after a
  // re-trace); one whose caller keeps every frame gets fresh images each time. Frame after frame
  // the visitor moves, and the eye moves twice (static images traced again): the two must agree bit
  // for bit, and the kept frames must not change. At a fixed exposure the static display is
  // composed over too; at an automatic one the display is tone-mapped from the composed image.
  const SphereScene s;
  for (const float exposure : {1.5f, 0.0f}) {
    SCOPED_TRACE(exposure);
    TracerSettings tracer = settings(1, true);
    tracer.exposure = exposure;
    FrameRenderer written_again(s.scene, s.ibl, tracer);
    FrameRenderer kept(s.scene, s.ibl, tracer);
    std::vector<FrameResult> kept_frames;
    std::vector<cv::Mat> kept_copies;
    std::size_t buffers_written_again = 0, static_reused = 0;
    const uchar* last_hdr = nullptr;
    for (int f = 0; f < 8; ++f) {
      ForegroundCloud visitor = s.wall;
      for (ForegroundPoint& p : visitor.points) p.position.x += 0.03f * float(f % 4);
      const vec3 eye = f < 3 ? kEye : f < 6 ? kEye + vec3(0.1f, 0.0f, 0.0f) : kEye;
      const CameraModel view = s.view(eye);
      const FrameResult k = kept.render(visitor, {s.camera}, {view});
      const FrameResult a = written_again.render(visitor, {s.camera}, {view});
      const ViewImages& va = a.views.at(0);
      const ViewImages& vk = k.views.at(0);
      ASSERT_TRUE(a.plan.has(Pass::ForegroundWalk)) << a.plan.describe();
      EXPECT_GT(va.composed_pixels, 0u) << "frame " << f;
      EXPECT_EQ(cv::norm(va.hdr, vk.hdr, cv::NORM_INF), 0.0) << "frame " << f;
      EXPECT_EQ(cv::norm(va.weight, vk.weight, cv::NORM_INF), 0.0) << "frame " << f;
      EXPECT_EQ(cv::norm(va.display, vk.display, cv::NORM_INF), 0.0) << "frame " << f;
      buffers_written_again += va.hdr.data == last_hdr;
      static_reused += va.static_reused;
      last_hdr = va.hdr.data;
      kept_frames.push_back(k);
      kept_copies.push_back(vk.hdr.clone());
      kept_copies.push_back(vk.weight.clone());
      kept_copies.push_back(vk.display.clone());
    }
    // Both ways of writing again ran: after a re-trace and over reused static images.
    EXPECT_GE(static_reused, 4u);
    EXPECT_GE(buffers_written_again, 6u);
    for (std::size_t f = 0; f < kept_frames.size(); ++f) {
      const ViewImages& v = kept_frames[f].views.at(0);
      EXPECT_EQ(cv::norm(v.hdr, kept_copies[3 * f], cv::NORM_INF), 0.0) << "frame " << f;
      EXPECT_EQ(cv::norm(v.weight, kept_copies[3 * f + 1], cv::NORM_INF), 0.0) << "frame " << f;
      EXPECT_EQ(cv::norm(v.display, kept_copies[3 * f + 2], cv::NORM_INF), 0.0) << "frame " << f;
    }
  }
}

TEST(FrameRenderer, RejectsBadReuseAndEdgeSettings) {
  const SphereScene s;
  TracerSettings bad = settings(1, true, -1.0f);
  EXPECT_THROW(FrameRenderer(s.scene, s.ibl, bad), InputError);
  bad = settings(4, true);
  EXPECT_THROW(FrameRenderer(s.scene, s.ibl, bad), InputError);
  bad = settings(1, true, 0.01f);
  bad.static_retraces_per_frame = -1;
  EXPECT_THROW(FrameRenderer(s.scene, s.ibl, bad), InputError);
  bad.static_retraces_per_frame = 1;
  bad.static_defer_distance = 0.005f;  // below the reuse distance: every moved eye would trace
  EXPECT_THROW(FrameRenderer(s.scene, s.ibl, bad), InputError);
}

TEST(StaticPassSchedule, TracesTheLongestWaitingFirstAndWhatCannotWaitBeforeTheBudget) {
  const auto state = [](bool shown, bool reuse, bool defer, float moved, int waited) {
    ViewReuseState s;
    s.cache_shown = shown;
    s.within_reuse = reuse;
    s.within_defer = defer;
    s.moved = moved;
    s.waited = waited;
    return s;
  };
  using P = StaticPass;
  // Three moved eyes that may wait: the one that waited longest traces, then the one moved farthest.
  std::vector<ViewReuseState> views = {state(true, false, true, 0.02f, 0), state(true, false, true, 0.01f, 2),
                                       state(true, false, true, 0.03f, 0), state(true, true, true, 0.0f, 0)};
  EXPECT_EQ(scheduleStaticPasses(views, 1), (std::vector<P>{P::Defer, P::Trace, P::Defer, P::Reuse}));
  EXPECT_EQ(scheduleStaticPasses(views, 2), (std::vector<P>{P::Defer, P::Trace, P::Trace, P::Reuse}));
  // No budget: every moved eye traces.
  EXPECT_EQ(scheduleStaticPasses(views, 0), (std::vector<P>{P::Trace, P::Trace, P::Trace, P::Reuse}));
  // A view without a cache to show and an eye beyond the defer distance trace whatever the budget,
  // and take it from the others.
  views[0] = state(false, false, false, 0.0f, 0);
  views[3] = state(true, false, false, 0.2f, 0);
  EXPECT_EQ(scheduleStaticPasses(views, 1), (std::vector<P>{P::Trace, P::Defer, P::Defer, P::Trace}));
  EXPECT_EQ(scheduleStaticPasses(views, 3), (std::vector<P>{P::Trace, P::Trace, P::Defer, P::Trace}));
}

TEST(FrameRenderer, ABudgetOfOneRetraceTracesEveryMovedEyeWithinAsManyFramesAsViews) {
  const SphereScene s;
  TracerSettings budget = settings(1, true, 0.01f);
  budget.static_retraces_per_frame = 1;
  budget.static_defer_distance = 0.1f;
  FrameRenderer renderer(s.scene, s.ibl, budget);
  const std::vector<vec3> eyes = {kEye, vec3(1.2f, 0.3f, 0.0f), vec3(0.0f, 0.5f, -1.2f)};
  const auto frame = [&](const vec3& offset) {
    std::vector<CameraModel> views;
    for (const vec3& eye : eyes) views.push_back(s.view(eye + offset));
    return renderer.render(s.wall, {s.camera}, views);
  };
  // The first frame has nothing cached: every view traces, the budget notwithstanding.
  for (const ViewImages& v : frame(vec3(0.0f)).views) EXPECT_FALSE(v.static_reused);
  // Every eye moves 3 cm and then stays: one view a frame traces, the others show their cache
  // from the eye they were traced from, until each has traced from where its eye now is.
  const vec3 moved(0.03f, 0.0f, 0.0f);
  std::vector<int> traced_in(eyes.size(), -1);
  for (int f = 0; f < 3; ++f) {
    const FrameResult result = frame(moved);
    int traced = 0;
    for (std::size_t v = 0; v < eyes.size(); ++v) {
      const ViewImages& view = result.views[v];
      if (!view.static_reused) {
        ++traced;
        EXPECT_EQ(traced_in[v], -1) << "view " << v << " traced twice";
        traced_in[v] = f;
        EXPECT_EQ(view.camera.position(), eyes[v] + moved);
      } else {
        EXPECT_EQ(view.static_deferred, traced_in[v] == -1) << "view " << v << ", frame " << f;
        EXPECT_EQ(view.camera.position(), traced_in[v] == -1 ? eyes[v] : eyes[v] + moved);
      }
    }
    EXPECT_EQ(traced, 1) << "frame " << f;
  }
  for (std::size_t v = 0; v < eyes.size(); ++v) EXPECT_GE(traced_in[v], 0) << "view " << v;
  // A deferred view shows exactly what a renderer whose reuse distance covers the move shows.
  FrameRenderer wide(s.scene, s.ibl, settings(1, true, 0.05f));
  wide.render(s.wall, {s.camera}, {s.view(eyes[0])});
  FrameRenderer deferring(s.scene, s.ibl, budget);
  deferring.render(s.wall, {s.camera}, {s.view(eyes[0]), s.view(eyes[1])});
  const FrameResult both_moved =
      deferring.render(s.wall, {s.camera}, {s.view(eyes[0] + moved), s.view(eyes[1] + moved * 2.0f)});
  ASSERT_TRUE(both_moved.views[0].static_deferred) << "the farther moved eye traces first";
  EXPECT_FALSE(both_moved.views[1].static_reused);
  const ViewImages reused = wide.render(s.wall, {s.camera}, {s.view(eyes[0] + moved)}).views.at(0);
  ASSERT_TRUE(reused.static_reused);
  EXPECT_EQ(cv::norm(both_moved.views[0].display, reused.display, cv::NORM_INF), 0.0);
  // An eye beyond the defer distance traces whatever the budget.
  const FrameResult far = frame(vec3(0.3f, 0.0f, 0.0f));
  for (const ViewImages& v : far.views) EXPECT_FALSE(v.static_reused);
}

}  // namespace
}  // namespace holo::reflect
