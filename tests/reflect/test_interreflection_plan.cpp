// Where the interreflection casts rays (effect_plan.hpp, RenderScene::mayMeetRelicAgain): on the
// concave built-in relics every mirror ray that meets the relic, found by casting them all, is one
// the renderer casts, and every lobe direction it skips misses; a convex relic casts none and its
// picture is the one without the effect, to the bit; the share of samples that trace is counted.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "static_shading.hpp"

namespace holo::reflect {
namespace {

// Views of the relic from the side, from above and from below, 64x64, the relic filling about a
// third of each.
std::vector<CameraModel> viewsAround(const Bounds3& b) {
  const vec3 centre = 0.5f * (b.lo + b.hi);
  const float reach = 2.5f * glm::length(b.hi - b.lo);
  std::vector<CameraModel> views;
  for (const vec3& from : {vec3(0.3f, 0.1f, 1.0f), vec3(-0.4f, 1.0f, 0.6f), vec3(0.5f, -0.8f, -0.4f)})
    views.push_back(lookAtCamera(centre + reach * glm::normalize(from), centre, 25.0f, 64, 64));
  return views;
}

// The point a ray from a hit point leaves from, as the static shading casts it.
Ray rayFrom(const HitPoint& h, const vec3& direction) {
  return Ray{h.position + h.normal * TracerSettings{}.ray_offset, direction};
}

struct BruteForce {
  int samples = 0, truly_meeting = 0, missed_by_the_plan = 0;
  int lobe_skipped = 0, lobe_skipped_meeting = 0;
};

// Casts every sample's mirror ray and 16 seeded directions of its hemisphere against the relic.
BruteForce castEverything(const RenderScene& scene, const std::vector<CameraModel>& views) {
  BruteForce out;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const CameraModel& view : views) {
    HitPointBuffer hits;
    traceHitPoints(scene, view, AntiAliasing::None, hits);
    for (const std::uint32_t p : hits.covered) {
      const HitPoint& h = hits.hits[p];
      ++out.samples;
      if (scene.relicOnly().intersect(rayFrom(h, h.reflected)).hit()) {
        ++out.truly_meeting;
        if (!h.mirror_may_meet_relic) ++out.missed_by_the_plan;
      }
      for (int k = 0; k < 16; ++k) {
        vec3 d(u(rng), u(rng), u(rng));
        if (!(glm::length(d) > 0.1f)) continue;
        d = glm::normalize(d);
        if (glm::dot(d, h.normal) < 0.0f) d = -d;
        if (scene.mayMeetRelicAgain(h.location.mesh, h.location.triangle, h.location.front, d)) continue;
        ++out.lobe_skipped;
        if (scene.relicOnly().intersect(rayFrom(h, d)).hit()) ++out.lobe_skipped_meeting;
      }
    }
  }
  return out;
}

TEST(InterreflectionPlan, EveryMirrorRayThatMeetsAConcaveRelicIsCast) {
  for (const std::string name : {"vase", "bowl", "kettle"}) {
    SCOPED_TRACE(name);
    const RenderScene scene(relics::makeRelic(name), {});
    ASSERT_FALSE(scene.relicIsConvex());
    const BruteForce b = castEverything(scene, viewsAround(scene.relicBounds()));
    std::printf(
        "%s: %d samples, %d mirror rays meet the relic, %d of them not cast; %d lobe directions "
        "skipped, %d of them meeting it\n",
        name.c_str(), b.samples, b.truly_meeting, b.missed_by_the_plan, b.lobe_skipped,
        b.lobe_skipped_meeting);
    ASSERT_GT(b.samples, 1000);
    EXPECT_GT(b.truly_meeting, 0) << "a concave relic sees itself somewhere";
    EXPECT_EQ(b.missed_by_the_plan, 0);
    EXPECT_GT(b.lobe_skipped, 1000) << "the planes prove misses for lobe directions too";
    EXPECT_EQ(b.lobe_skipped_meeting, 0);
  }
}

// The counters of the static shading: the samples that cast an interreflection ray are those the
// relic's shape allows, a share of the concave relics' samples and none of the sphere's.
TEST(InterreflectionPlan, OnlySamplesThatCanSeeTheRelicCastRays) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16});
  const TracerSettings settings;
  for (const std::string name : {"sphere", "vase", "bowl", "kettle"}) {
    SCOPED_TRACE(name);
    const RenderScene scene(relics::makeRelic(name), {});
    StaticCounts total;
    for (const CameraModel& view : viewsAround(scene.relicBounds())) {
      HitPointBuffer hits;
      traceHitPoints(scene, view, AntiAliasing::None, hits);
      std::vector<SplitSumShading> shading;
      std::vector<WalkRay> walk_rays;
      ViewBounces bounces;
      cv::Mat hdr(view.height(), view.width(), CV_32FC3, cv::Scalar::all(0));
      cv::Mat coverage(view.height(), view.width(), CV_32FC1, cv::Scalar(0));
      TracerSettings planned = settings;
      planned.relic_interreflection = !scene.relicIsConvex();  // as the effect plan decides
      total.add(StaticShading(scene, ibl, planned, nullptr)
                    .shade(hits, view, shading, walk_rays, bounces, hdr, coverage));
    }
    const double share = double(total.interreflected_samples) / double(total.shaded_samples);
    std::printf("%s: %.1f%% of %llu samples cast %llu interreflection rays\n", name.c_str(), 100.0 * share,
                static_cast<unsigned long long>(total.shaded_samples),
                static_cast<unsigned long long>(total.interreflection_rays));
    ASSERT_GT(total.shaded_samples, 1000u);
    if (name == "sphere") {
      EXPECT_EQ(total.interreflection_rays, 0u);
    } else {
      EXPECT_GT(total.interreflection_rays, 0u);
      EXPECT_LT(share, 0.95) << "the supporting planes spare part of every relic here";
    }
  }
}

// A convex relic: the plan leaves the effect off, no ray is cast and the picture is the one with
// the effect switched off, to the bit. The plan drops only rays that would meet the relic from
// inside: at the limbs a mirror ray about the smooth normal dips below its flat triangle and
// crosses the solid.
TEST(InterreflectionPlan, AConvexRelicCastsNoRayAndShowsTheSamePicture) {
  const RenderScene scene(relics::makeRelic("sphere"), {});
  ASSERT_TRUE(scene.relicIsConvex());
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{5, 16, 16});
  TracerSettings on, off;
  off.relic_interreflection = false;
  FrameRenderer with(scene, ibl, on), without(scene, ibl, off);
  const std::vector<CameraModel> views = viewsAround(scene.relicBounds());
  const FrameResult a = with.render(depthfilter::ForegroundCloud{}, {}, views);
  const FrameResult b = without.render(depthfilter::ForegroundCloud{}, {}, views);
  EXPECT_FALSE(a.plan.interreflection) << a.plan.describe();
  EXPECT_NE(a.plan.describe().find("convex relic: no interreflection"), std::string::npos);
  for (std::size_t v = 0; v < views.size(); ++v) {
    EXPECT_EQ(a.views[v].interreflection_rays, 0u);
    EXPECT_GT(a.views[v].shaded_samples, 0u);
    EXPECT_EQ(cv::norm(a.views[v].hdr, b.views[v].hdr, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(a.views[v].display, b.views[v].display, cv::NORM_INF), 0.0);
  }
  // Every mirror ray that meets the sphere meets it from inside (leaving through the far side).
  const vec3 centre = 0.5f * (scene.relicBounds().lo + scene.relicBounds().hi);
  int inside = 0;
  for (const CameraModel& view : views) {
    HitPointBuffer hits;
    traceHitPoints(scene, view, AntiAliasing::None, hits);
    for (const std::uint32_t p : hits.covered) {
      const Ray ray = rayFrom(hits.hits[p], hits.hits[p].reflected);
      const RayHit hit = scene.relicOnly().intersect(ray);
      if (!hit.hit()) continue;
      ++inside;
      EXPECT_GT(glm::dot(ray.direction, ray.origin + hit.t * ray.direction - centre), 0.0f) << "pixel " << p;
    }
  }
  std::printf("sphere: %d limb mirror rays cross the solid\n", inside);
}

TEST(InterreflectionPlan, ThePlanRunsTheEffectWhereTheRelicCanSeeItself) {
  EffectInputs in;
  in.relic_bounds = {vec3(-0.1f), vec3(0.1f)};
  EXPECT_TRUE(planEffects(in).interreflection);
  in.relic_convex = true;
  EXPECT_FALSE(planEffects(in).interreflection);
  in.relic_convex = false;
  in.interreflection = false;
  EXPECT_FALSE(planEffects(in).interreflection);
  EXPECT_NE(planEffects(in).describe().find("interreflection off"), std::string::npos);
}

}  // namespace
}  // namespace holo::reflect
