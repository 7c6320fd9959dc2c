// The relic's self-occlusion (relic_visibility.hpp) and the rough interreflection's lobe against
// path-traced truth on the concave built-in bowl, the relic that calls for them: the inside of a
// Lambert bowl lit by unoccluded irradiance is too bright, and switching the visibility off must
// make the error grow; a convex relic does none of the work (counters). Small in CI (a synthetic
// sky, 40x40 views); the figures of docs/tracer/self_occlusion.md come from
// `HOLO_FULL_EVAL=1 test_self_occlusion --gtest_filter='*Figures*'` (two real panoramas of
// ../shared/data, 128x128 views, 1024 spp truth; HOLO_FIGURES_RELIC=bowl for one relic's).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/image.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/relic_visibility.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "shared_data.hpp"

namespace holo::reflect {
namespace {

// A sky over a darker ground, with a warm bright patch low on one side: light that the bowl's rim
// hides from the inside.
cv::Mat skyPanorama(int w, int h) {
  cv::Mat pano(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = (float(y) + 0.5f) / float(h);  // 0 at the zenith
      vec3 rgb = v < 0.5f ? vec3(0.6f, 0.8f, 1.2f) * (1.2f - v) : vec3(0.25f, 0.2f, 0.15f);
      if (v > 0.35f && v < 0.5f && x < w / 8) rgb = vec3(6.0f, 4.0f, 2.5f);
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(rgb.z, rgb.y, rgb.x);
    }
  return pano;
}

// Pixels whose whole 3x3 neighbourhood's centre rays meet the inside of the bowl (the inner wall
// and floor: facing a point above the middle of the opening, within 0.93 of the rim's radius).
cv::Mat insideMask(const RenderScene& scene, const CameraModel& view) {
  const Bounds3 b = scene.relicBounds();
  const vec3 above(0.0f, b.hi.y, 0.0f);
  const float rim = 0.5f * b.extent().x;
  cv::Mat inside(view.height(), view.width(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x) {
      HitPoint hp;
      if (!traceHitPoint(scene, view, vec2(float(x), float(y)), hp)) continue;
      const float radial = glm::length(vec2(hp.position.x, hp.position.z));
      if (glm::dot(hp.normal, above - hp.position) > 0.0f && radial < 0.93f * rim)
        inside.at<std::uint8_t>(y, x) = 1;
    }
  cv::Mat eroded;
  cv::erode(inside, eroded, cv::Mat::ones(3, 3, CV_8UC1));
  return eroded;
}

// Looking into the bowl from the face's side, 55 degrees above the horizon.
CameraModel bowlView(const Bounds3& b, int size) {
  const vec3 target(0.0f, 0.45f * b.hi.y, 0.0f);
  const vec3 eye = target + 0.75f * vec3(0.0f, std::sin(glm::radians(55.0f)), std::cos(glm::radians(55.0f)));
  return lookAtCamera(eye, target, framingFovDeg(eye, b), size, size);
}

// The metal bowl's suspects against the defaults: the lobe's strata at their centres, the second
// point's mirror ray followed once, and both (the earlier defaults).
struct MetalBowlSuspects {
  TracerSettings centres, one_bounce, earlier;
};

MetalBowlSuspects metalBowlSuspects() {
  MetalBowlSuspects s;
  s.centres.evaluation.lobe_strata_jittered = false;
  s.one_bounce.rough_interreflection_mirror_bounces = 1;
  s.earlier = s.centres;
  s.earlier.rough_interreflection_mirror_bounces = 1;
  return s;
}

struct RegionError {
  double mean_ours = 0, mean_truth = 0, rmse = 0;  // luminance over the region
  int pixels = 0;
  double meanRatio() const { return mean_ours / mean_truth; }
};

RegionError regionError(const cv::Mat& ours, const cv::Mat& truth, const cv::Mat& region) {
  RegionError e;
  double sq = 0;
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x) {
      if (!region.at<std::uint8_t>(y, x)) continue;
      const double a = luminance(rgbAt(ours, x, y)), t = luminance(rgbAt(truth, x, y));
      e.mean_ours += a;
      e.mean_truth += t;
      sq += (a - t) * (a - t);
      ++e.pixels;
    }
  if (e.pixels == 0) return e;
  e.mean_ours /= e.pixels;
  e.mean_truth /= e.pixels;
  e.rmse = std::sqrt(sq / e.pixels);
  return e;
}

struct OursRender {
  cv::Mat hdr;
  double ms = 0;             // the view's static passes (hit points, static shading)
  double visibility_ms = 0;  // building the renderer (the relic's visibility included)
  double lighting_ms = 0;    // lighting the visibility's vertices under the IBL (first frame)
  std::uint64_t visibility_rays = 0;
  FrameResult frame;
};

OursRender renderOurs(const RenderScene& scene, const PrefilteredIbl& ibl, const CameraModel& view,
                      const TracerSettings& settings) {
  OursRender out;
  const Stopwatch build;
  FrameRenderer renderer(scene, ibl, settings);
  out.visibility_ms = build.ms();
  if (renderer.visibility()) out.visibility_rays = renderer.visibility()->rays();
  out.frame = renderer.render({}, {}, {view});
  out.hdr = out.frame.views.at(0).hdr;
  for (const PassTiming& t : out.frame.frame_timings)
    if (t.pass == Pass::SelfOcclusion) out.lighting_ms += t.ms;
  for (const PassTiming& t : out.frame.views.at(0).timings)
    if (t.pass == Pass::HitPoints || t.pass == Pass::StaticReflections) out.ms += t.ms;
  return out;
}

// Before: no visibility and the mirror ray at every roughness.
TracerSettings beforeSettings() {
  TracerSettings s;
  s.evaluation.self_occlusion = false;
  s.rough_interreflection_roughness = 2.0f;
  return s;
}

// An open direction's transfer is the clamped cosine's: under the IBL's coefficients turned into the
// relic's frame it gives the IBL's own irradiance, with the relic turned as well as not.
// CI's size: 64 rays per vertex instead of the default 256 (a quarter of the visibility's rays;
// the figures hold the bars on the defaults).
TracerSettings ciSettings() {
  TracerSettings s;
  s.self_occlusion_rays = 64;
  return s;
}

TEST(SelfOcclusion, RelicFrameRadianceFollowsTheTurn) {
  const Environment env(skyPanorama(64, 32));
  PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  for (float angle : {0.0f, 0.7f, -2.5f}) {
    ibl.setRelicTurn(vec3(0.1f, 0.0f, -0.2f), angle);
    const std::array<vec3, 9> radiance = ibl.relicFrameRadiance();
    for (const vec3& n : {vec3(1, 0, 0), vec3(0, 1, 0), glm::normalize(vec3(0.3f, -0.5f, 0.8f)),
                          glm::normalize(vec3(-0.9f, 0.2f, -0.1f))}) {
      const auto y = IrradianceSH::basis(n);
      vec3 e(0.0f);
      for (int i = 0; i < 9; ++i) e += IrradianceSH::kCosineLobe[i] * y[i] * radiance[i];
      const vec3 expected = ibl.irradiance(n);
      EXPECT_LT(glm::length(e - expected), 1e-4f * glm::length(expected) + 1e-5f) << angle;
    }
  }
}

// A floor of two triangles with a cube standing on its middle, under an even white hall: the floor's
// four corners are far from the cube and see the whole sky, so their interpolation lights the floor
// beside the cube as if nothing stood there. The lattice of points the long triangles get gives the
// floor there the cube's shadow: held to the share of the cosine-weighted sky the cube leaves open,
// counted over 4096 rays, and switching the lattice off must miss it.
TEST(SelfOcclusion, ATwoTriangleFloorShowsTheShadowOfWhatStandsOnIt) {
  Model model;
  model.materials.resize(1);
  model.materials[0].base_colour = vec3(0.8f);
  TriangleMesh floor;
  floor.positions = {{-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f}};
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  floor.computeNormals();
  TriangleMesh cube;
  for (int corner = 0; corner < 8; ++corner)
    cube.positions.push_back(
        {corner & 1 ? 0.2f : -0.2f, corner & 2 ? 0.4f : 0.0f, corner & 4 ? 0.2f : -0.2f});
  cube.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  cube.computeNormals();
  model.meshes = {floor, cube};
  const RenderScene scene(model, {});
  ASSERT_GT(glm::dot(scene.relic().meshes[0].normals[0], vec3(0.0f, 1.0f, 0.0f)), 0.99f);
  const Environment env(cv::Mat(32, 64, CV_32FC3, cv::Scalar(1.0f, 1.0f, 1.0f)));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});

  // The floor 5 cm beside the cube's face.
  const vec3 beside(0.25f, 0.0f, 0.0f);
  const Ray down{beside + vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, -1.0f, 0.0f)};
  const RayHit hit = scene.relicOnly().intersect(down);
  ASSERT_TRUE(hit.hit());
  const SurfaceLocation at = resolveSurface(scene, scene.relicOnly(), down, hit, 0.0f).location;
  ASSERT_TRUE(at.located());
  ASSERT_EQ(at.mesh, 0u);

  int open = 0;
  constexpr int kRays = 4096;
  for (int k = 0; k < kRays; ++k) {  // cosine-distributed, stratified 64 x 64
    const float u1 = (float(k % 64) + 0.5f) / 64.0f, u2 = (float(k / 64) + 0.5f) / 64.0f;
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    const vec3 d(r * std::cos(phi), std::sqrt(1.0f - u1), r * std::sin(phi));
    if (!scene.relicOnly().intersect({beside + 1e-3f * vec3(0.0f, 1.0f, 0.0f), d}).hit()) ++open;
  }
  const float truth = float(open) / float(kRays);
  ASSERT_LT(truth, 0.9f);  // the cube hides a real share of the sky there

  RelicVisibilitySettings settings;
  settings.bounces = 0;
  settings.rays_per_vertex = 64;
  const RelicVisibility with_lattice(scene, settings);
  settings.lattice_steps_per_relic = 0.0f;
  const RelicVisibility vertices_only(scene, settings);
  // Under an even hall of radiance 1 the open share's irradiance is pi times it.
  const float lattice_share = with_lattice.irradiance(with_lattice.lit(ibl), at).g / kPi;
  const float vertex_share = vertices_only.irradiance(vertices_only.lit(ibl), at).g / kPi;
  std::printf("open share beside the cube: truth %.3f, with the lattice %.3f, vertices only %.3f\n", truth,
              lattice_share, vertex_share);
  // Measured 0.584 (truth), 0.641 with the lattice (its points 12 cm apart, the point 5 cm from the
  // cube where the shadow is steepest), 0.988 with the vertices only.
  EXPECT_NEAR(lattice_share, truth, 0.08f);
  EXPECT_GT(std::abs(vertex_share - truth), 3.0f * std::abs(lattice_share - truth));
  EXPECT_GT(vertex_share - truth, 0.1f);
  RelicVisibilitySettings bad;
  bad.lattice_steps_per_relic = 100.0f;
  EXPECT_THROW(RelicVisibility(scene, bad), InputError);
}

TEST(SelfOcclusion, ConvexRelicDoesNoneOfTheWork) {
  const Environment env(skyPanorama(64, 32));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  const RenderScene sphere(relics::makeRelic("sphere"), {});
  ASSERT_TRUE(sphere.relicIsConvex());
  FrameRenderer convex(sphere, ibl);
  EXPECT_EQ(convex.visibility(), nullptr);
  const CameraModel view = bowlView(sphere.relicBounds(), 24);
  const FrameResult r = convex.render({}, {}, {view});
  EXPECT_FALSE(r.plan.has(Pass::SelfOcclusion)) << r.plan.describe();
  EXPECT_EQ(r.views.at(0).occluded_samples, 0u);

  const RenderScene bowl(relics::makeRelic("bowl"), {});
  ASSERT_FALSE(bowl.relicIsConvex());
  FrameRenderer concave(bowl, ibl, ciSettings());
  ASSERT_NE(concave.visibility(), nullptr);
  EXPECT_GT(concave.visibility()->rays(), 0u);
  EXPECT_GT(concave.visibility()->maxOcclusion(), 0.4f);  // the floor sees much of the walls
  const FrameResult c = concave.render({}, {}, {bowlView(bowl.relicBounds(), 24)});
  EXPECT_TRUE(c.plan.has(Pass::SelfOcclusion)) << c.plan.describe();
  EXPECT_GT(c.views.at(0).occluded_samples, 0u);

  // The same bowl all metal: its lobes trace their own interreflection, no diffuse part to occlude.
  const RenderScene metal(relics::makeRelic("metal-bowl"), {});
  FrameRenderer metal_renderer(metal, ibl);
  EXPECT_EQ(metal_renderer.visibility(), nullptr);
  const FrameResult m = metal_renderer.render({}, {}, {bowlView(metal.relicBounds(), 24)});
  EXPECT_FALSE(m.plan.has(Pass::SelfOcclusion)) << m.plan.describe();
  EXPECT_EQ(m.views.at(0).occluded_samples, 0u);
}

// The plan leaves the visibility off where its largest displayed change is below one sRGB code:
// the bowl's hall dimmed a thousandfold at the exposure the bright hall fixed (a frame loop's
// evening). Forced on (effect_min_codes 0) it does its lookups and changes the radiance, yet no
// displayed pixel by a code; in the bright hall it shows and the plan runs it.
TEST(SelfOcclusion, PlanLeavesItOffBelowOneDisplayedCode) {
  const RenderScene bowl(relics::makeRelic("bowl"), {});
  const CameraModel view = bowlView(bowl.relicBounds(), 24);
  const Environment bright_env(skyPanorama(64, 32));
  const PrefilteredIbl bright(bright_env, PrefilterOptions{6, 32, 16});
  FrameRenderer day(bowl, bright, ciSettings());
  const FrameResult shown = day.render({}, {}, {view});
  EXPECT_TRUE(shown.plan.has(Pass::SelfOcclusion)) << shown.plan.describe();
  EXPECT_NE(shown.plan.describe().find("sRGB codes under this light"), std::string::npos);
  EXPECT_GT(shown.views.at(0).occluded_samples, 0u);

  const Environment dim_env(skyPanorama(64, 32) * 0.001);
  const PrefilteredIbl dim(dim_env, PrefilterOptions{6, 32, 16});
  TracerSettings evening = ciSettings();
  evening.exposure = autoExposure(shown.views.at(0).hdr);
  FrameRenderer gated(bowl, dim, evening);
  const FrameResult off = gated.render({}, {}, {view});
  EXPECT_FALSE(off.plan.has(Pass::SelfOcclusion)) << off.plan.describe();
  EXPECT_NE(off.plan.describe().find("self-occlusion not shown"), std::string::npos) << off.plan.describe();
  EXPECT_EQ(off.views.at(0).occluded_samples, 0u);

  evening.effect_min_codes = 0.0f;
  FrameRenderer forced(bowl, dim, evening);
  const FrameResult on = forced.render({}, {}, {view});
  ASSERT_TRUE(on.plan.has(Pass::SelfOcclusion)) << on.plan.describe();
  EXPECT_GT(on.views.at(0).occluded_samples, 0u);
  const cv::Mat& a = off.views.at(0).hdr;
  const cv::Mat& b = on.views.at(0).hdr;
  float radiance_change = 0.0f, codes_change = 0.0f;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const vec3 ra = rgbAt(a, x, y), rb = rgbAt(b, x, y);
      radiance_change =
          std::max(radiance_change, maxComponent(glm::abs(ra - rb)) / std::max(maxComponent(ra), 1e-12f));
      codes_change = std::max(codes_change, maxComponent(glm::abs(toneMapCodes(ra, evening.exposure) -
                                                                  toneMapCodes(rb, evening.exposure))));
    }
  std::printf(
      "bright: %s\ndim at the bright exposure: %s\nforced on: largest radiance change %.0f%%, %.2f codes\n",
      shown.plan.describe().c_str(), off.plan.describe().c_str(), double(radiance_change) * 100.0,
      double(codes_change));
  EXPECT_GT(radiance_change, 0.1f);  // the visibility darkens the inside by tens of percent
  EXPECT_LT(codes_change, 1.0f);
}

// The inside of the Lambert bowl against the path tracer: with the visibility its mean is close
// and its per-pixel error well below the unoccluded irradiance's, which is too bright.
TEST(SelfOcclusion, LambertBowlInsideMatchesTruthAndWorsensWithoutIt) {
  constexpr int kSize = 40, kSpp = 256;
  const Environment env(skyPanorama(128, 64));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  const RenderScene scene(relics::makeRelic("bowl"), {});
  const CameraModel view = bowlView(scene.relicBounds(), kSize);
  const cv::Mat region = insideMask(scene, view);
  ASSERT_GT(cv::countNonZero(region), 150);
  const cv::Mat truth = reference::renderPathTraced(reference::PathTracer(scene, env), view, kSpp);
  const RegionError with = regionError(renderOurs(scene, ibl, view, ciSettings()).hdr, truth, region);
  const RegionError without = regionError(renderOurs(scene, ibl, view, beforeSettings()).hdr, truth, region);
  std::printf(
      "Lambert bowl inside, %d px: mean ours/truth %.3f with the visibility, %.3f without; "
      "rmse %.4f vs %.4f (ratio %.2f)\n",
      with.pixels, with.meanRatio(), without.meanRatio(), with.rmse, without.rmse, without.rmse / with.rmse);
  EXPECT_GT(without.meanRatio(), 1.06);  // unoccluded: too bright
  EXPECT_NEAR(with.meanRatio(), 1.0, 0.04);
  EXPECT_LT(with.rmse, 0.5 * without.rmse);
  // A turning relic (here turned by a ten-thousandth of a radian: the same light) is lit from the
  // transfer alone: coarser, still far nearer the truth than the unoccluded light.
  PrefilteredIbl turned(env, PrefilterOptions{6, 32, 16});
  turned.setRelicTurn(vec3(0.0f), 1e-4f);
  const RegionError transfer = regionError(renderOurs(scene, turned, view, ciSettings()).hdr, truth, region);
  std::printf("turning: mean ours/truth %.3f, rmse %.4f\n", transfer.meanRatio(), transfer.rmse);
  EXPECT_NEAR(transfer.meanRatio(), 1.0, 0.07);
  EXPECT_LT(transfer.rmse, 0.7 * without.rmse);
}

// The rough metal bowl's lobes against the path tracer: each lobe's hall share weighted by where
// the hall's light is (the bright patch low on one side that the rim hides from the inside) must be
// measurably nearer the truth than the same share by the open samples' count alone.
TEST(SelfOcclusion, RoughLobeVisibilityWeightedByTheLightBringsTheMetalBowlNearer) {
  constexpr int kSize = 40, kSpp = 256;
  const Environment env(skyPanorama(128, 64));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  const RenderScene scene(relics::makeRelic("metal-bowl"), {});
  const CameraModel view = bowlView(scene.relicBounds(), kSize);
  const cv::Mat region = insideMask(scene, view);
  ASSERT_GT(cv::countNonZero(region), 150);
  const cv::Mat truth = reference::renderPathTraced(reference::PathTracer(scene, env), view, kSpp);
  TracerSettings unweighted;
  unweighted.evaluation.lobe_visibility = false;
  const RegionError with = regionError(renderOurs(scene, ibl, view, {}).hdr, truth, region);
  const RegionError without = regionError(renderOurs(scene, ibl, view, unweighted).hdr, truth, region);
  const RegionError before = regionError(renderOurs(scene, ibl, view, beforeSettings()).hdr, truth, region);
  std::printf(
      "metal bowl inside, %d px: mean ours/truth %.3f weighted by the light, %.3f by the count, %.3f "
      "mirror; rmse %.4f, %.4f, %.4f\n",
      with.pixels, with.meanRatio(), without.meanRatio(), before.meanRatio(), with.rmse, without.rmse,
      before.rmse);
  EXPECT_LT(with.rmse, 0.85 * without.rmse);  // measured 0.72x
  EXPECT_LT(with.rmse, before.rmse);
  EXPECT_NEAR(with.meanRatio(), 1.0, 0.05);

  // The lobe's strata at their centres (a midpoint rule that misses the lobe's tails) and the
  // second point's mirror ray followed once (the third point's lobe read as if open): each leaves
  // the inside's mean off the truth at full size (docs/tracer/self_occlusion.md); under this sky
  // the centres mainly add per-pixel error (one mirror bounce is within 4% of the default's).
  const auto [centres, one_bounce, earlier] = metalBowlSuspects();
  const RegionError at_centres = regionError(renderOurs(scene, ibl, view, centres).hdr, truth, region);
  const RegionError once = regionError(renderOurs(scene, ibl, view, one_bounce).hdr, truth, region);
  const RegionError both = regionError(renderOurs(scene, ibl, view, earlier).hdr, truth, region);
  std::printf(
      "mean ours/truth %.4f; strata at their centres %.4f, one mirror bounce %.4f, both %.4f; rmse %.4f, "
      "%.4f, %.4f, %.4f\n",
      with.meanRatio(), at_centres.meanRatio(), once.meanRatio(), both.meanRatio(), with.rmse,
      at_centres.rmse, once.rmse, both.rmse);
  EXPECT_NEAR(with.meanRatio(), 1.0, 0.03);
  EXPECT_LT(with.rmse, 0.95 * at_centres.rmse);  // measured 0.84x
  EXPECT_LT(with.rmse, 0.95 * both.rmse);        // measured 0.84x
}

// The Lambert bowl's lobe (roughness 1) read from the wide lobes' object-space cache instead of
// traced per sample: as near the truth as the per-sample strata (pooled and filtered). An eye that
// moves back and forth (a face following a visitor) redoes the view's static shading every frame:
// once it is back where it was, every entry it reads is kept, so its interreflection casts no ray,
// where the per-sample strata cast theirs again; and nothing is left to filter or refine.
TEST(SelfOcclusion, WideLobeCacheKeepsTheLambertBowlNearTruthAndAReturningEyeCastsNoRay) {
  constexpr int kSize = 40, kSpp = 128;
  const Environment env(skyPanorama(128, 64));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  const RenderScene scene(relics::makeRelic("bowl"), {});
  const CameraModel view = bowlView(scene.relicBounds(), kSize);
  cv::Mat relic(kSize, kSize, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      HitPoint hp;
      relic.at<std::uint8_t>(y, x) = traceHitPoint(scene, view, vec2(float(x), float(y)), hp) ? 1 : 0;
    }
  const cv::Mat truth = reference::renderPathTraced(reference::PathTracer(scene, env), view, kSpp);
  TracerSettings per_sample = ciSettings();
  per_sample.evaluation.wide_lobe_cache = false;
  const RegionError cached = regionError(renderOurs(scene, ibl, view, ciSettings()).hdr, truth, relic);
  const RegionError sampled = regionError(renderOurs(scene, ibl, view, per_sample).hdr, truth, relic);
  std::printf("Lambert bowl, %d px: rmse %.4f from the cache, %.4f per sample; mean ours/truth %.3f, %.3f\n",
              cached.pixels, cached.rmse, sampled.rmse, cached.meanRatio(), sampled.meanRatio());
  EXPECT_LT(cached.rmse, 1.03 * sampled.rmse);
  EXPECT_NEAR(cached.meanRatio(), sampled.meanRatio(), 0.01);

  // The eye 1 cm aside, then back: each frame's static shading is redone (no reuse).
  const vec3 target(0.0f, 0.45f * scene.relicBounds().hi.y, 0.0f);
  const CameraModel moved = lookAtCamera(view.position() + vec3(0.01f, 0.0f, 0.0f), target,
                                         framingFovDeg(view.position(), scene.relicBounds()), kSize, kSize);
  FrameRenderer with_cache(scene, ibl, ciSettings()), without_cache(scene, ibl, per_sample);
  FrameResult a, b;
  for (const CameraModel* eye : {&view, &moved, &view}) {
    a = with_cache.render({}, {}, {*eye});
    b = without_cache.render({}, {}, {*eye});
  }
  const ViewImages& va = a.views.at(0);
  const ViewImages& vb = b.views.at(0);
  std::printf("returning eye: %llu interreflection rays with the cache, %llu per sample\n",
              (unsigned long long)va.interreflection_rays, (unsigned long long)vb.interreflection_rays);
  ASSERT_FALSE(va.static_reused);
  ASSERT_GT(vb.interreflection_rays, 200u);
  EXPECT_EQ(va.interreflection_rays, 0u);
  EXPECT_FALSE(a.plan.has(Pass::AxisAlignedFilter)) << a.plan.describe();
  EXPECT_FALSE(a.plan.has(Pass::ProgressiveRefinement)) << a.plan.describe();
  // Per sample the lobe is sampled: refined, and the filter weighed by its own change (none
  // displayed on the clay, so left off after the first frame).
  EXPECT_TRUE(b.plan.has(Pass::ProgressiveRefinement)) << b.plan.describe();
  EXPECT_NE(b.plan.material_reason.find("axis-aligned filter not shown"), std::string::npos)
      << b.plan.describe();
}

// The figures (opt-in): Lambert and rough metal bowls under two real panoramas, and the kettle's
// handle and spout, ours against the path tracer with and without the effect.
TEST(SelfOcclusion, Figures) {
  if (!std::getenv("HOLO_FULL_EVAL")) GTEST_SKIP() << "HOLO_FULL_EVAL=1 renders the figures";
  const int size = 128, spp = 1024;
  const auto dir = test::scratchDir("self_occlusion");
  for (const std::string hdri : {"st_fagans_interior_1k.hdr", "empty_warehouse_01_1k.hdr"}) {
    HOLO_REQUIRE_SHARED_DATA("hdri/" + hdri);
    const Environment env(loadHdr(test::sharedData("hdri/" + hdri)).pixels);
    const PrefilteredIbl ibl(env);
    for (const std::string relic : {"bowl", "metal-bowl", "kettle"}) {
      // HOLO_FIGURES_RELIC=NAME renders that relic's figures alone.
      if (const char* only = std::getenv("HOLO_FIGURES_RELIC"); only && relic != only) continue;
      const RenderScene scene(relics::makeRelic(relic), {});
      const Bounds3 b = scene.relicBounds();
      CameraModel view = bowlView(b, size);
      cv::Mat region;
      if (relic == "kettle") {
        // The handle and the spout: relic pixels further from the axis than the body's radius.
        const vec3 eye(0.0f, 0.6f * b.hi.y, 0.8f);
        view = lookAtCamera(eye, b.center(), framingFovDeg(eye, b), size, size);
        region = cv::Mat(size, size, CV_8UC1, cv::Scalar(0));
        for (int y = 0; y < size; ++y)
          for (int x = 0; x < size; ++x) {
            HitPoint hp;
            if (traceHitPoint(scene, view, vec2(float(x), float(y)), hp) &&
                glm::length(vec2(hp.position.x, hp.position.z)) > 1.02f * 0.5f * b.extent().z)
              region.at<std::uint8_t>(y, x) = 1;
          }
      } else {
        region = insideMask(scene, view);
      }
      const Stopwatch gt_time;
      const cv::Mat truth = reference::renderPathTraced(reference::PathTracer(scene, env), view, spp);
      const double gt_ms = gt_time.ms();
      // The truth's own noise: a second truth with other samples; half their squared difference is
      // its variance, which every rmse below contains.
      reference::PathTracerOptions other_seed;
      other_seed.seed = 2;
      const double noise =
          regionError(reference::renderPathTraced(reference::PathTracer(scene, env, other_seed), view, spp),
                      truth, region)
              .rmse /
          std::sqrt(2.0);
      const OursRender on = renderOurs(scene, ibl, view, {});
      const OursRender off = renderOurs(scene, ibl, view, beforeSettings());
      const RegionError with = regionError(on.hdr, truth, region),
                        without = regionError(off.hdr, truth, region);
      std::printf(
          "%s %s: %d px; mean ours/truth %.4f with, %.4f without; rmse %.5f with, %.5f without "
          "(%.2fx lower); static passes %.1f ms with, %.1f ms without; renderer build %.0f ms with, "
          "%.0f ms without (%llu visibility rays), lighting them %.1f ms; truth %.0f ms\n",
          hdri.c_str(), relic.c_str(), with.pixels, with.meanRatio(), without.meanRatio(), with.rmse,
          without.rmse, without.rmse / with.rmse, on.ms, off.ms, on.visibility_ms, off.visibility_ms,
          (unsigned long long)on.visibility_rays, on.lighting_ms, gt_ms);
      const auto clean = [&](double rmse) { return std::sqrt(std::max(rmse * rmse - noise * noise, 0.0)); };
      std::printf(
          "  truth noise rmse %.5f, mean truth %.4f; without it: rmse %.5f with, %.5f without (%.2fx "
          "lower)\n",
          noise, with.mean_truth, clean(with.rmse), clean(without.rmse),
          clean(without.rmse) / clean(with.rmse));
      std::printf("  plan: %s\n", on.frame.plan.describe().c_str());
      if (relic != "kettle") {
        // Where the error lies: the bottom (within half the rim's radius), the wall, near the rim
        // (beyond 0.8 of it); rmse and mean of ours minus the truth.
        const float rim = 0.5f * b.extent().x;
        double sq[3] = {0, 0, 0}, bias[3] = {0, 0, 0};
        int n[3] = {0, 0, 0};
        for (int y = 0; y < size; ++y)
          for (int x = 0; x < size; ++x) {
            HitPoint hp;
            if (!region.at<std::uint8_t>(y, x) || !traceHitPoint(scene, view, vec2(float(x), float(y)), hp))
              continue;
            const float r = glm::length(vec2(hp.position.x, hp.position.z)) / rim;
            const int k = r < 0.5f ? 0 : r < 0.8f ? 1 : 2;
            const double d = luminance(rgbAt(on.hdr, x, y)) - luminance(rgbAt(truth, x, y));
            sq[k] += d * d;
            bias[k] += d;
            ++n[k];
          }
        std::printf("  where (rmse, mean error):");
        for (int k = 0; k < 3; ++k)
          std::printf(" %s %d px %.4f %+.4f",
                      k == 0   ? "bottom"
                      : k == 1 ? "wall"
                               : "rim",
                      n[k], n[k] ? std::sqrt(sq[k] / n[k]) : 0.0, n[k] ? bias[k] / n[k] : 0.0);
        std::printf("\n");
      }
      const float e = autoExposure(truth);
      const std::string stem = (dir / (hdri.substr(0, hdri.find('_')) + "_" + relic)).string();
      cv::imwrite(stem + "_truth.png", toneMap(truth, e));
      cv::imwrite(stem + "_with.png", toneMap(on.hdr, e));
      cv::imwrite(stem + "_without.png", toneMap(off.hdr, e));
      cv::imwrite(stem + "_region.png", region * 255);
      EXPECT_LT(with.rmse, without.rmse) << hdri << " " << relic;
    }
  }
}

// The metal bowl's suspects (opt-in): its inside's mean against truths of 5 and 16 bounces, and the
// light of one and of two bounces (truths of 1 and 2) against ours' open share alone and its
// met share; ours with the strata at their centres, one mirror bounce after the second point,
// both (the earlier default), strata 2x2 and 8x8 (8x8 at every sample), the hall share by the
// open count and the filter off. HOLO_SUSPECT_SIZE (default 64) and HOLO_SUSPECT_SPP (default 256).
TEST(SelfOcclusion, MetalBowlSuspects) {
  if (!std::getenv("HOLO_FULL_EVAL")) GTEST_SKIP() << "HOLO_FULL_EVAL=1 renders the figures";
  const int size = std::getenv("HOLO_SUSPECT_SIZE") ? std::atoi(std::getenv("HOLO_SUSPECT_SIZE")) : 64;
  const int spp = std::getenv("HOLO_SUSPECT_SPP") ? std::atoi(std::getenv("HOLO_SUSPECT_SPP")) : 256;
  for (const std::string hdri : {"st_fagans_interior_1k.hdr", "empty_warehouse_01_1k.hdr"}) {
    HOLO_REQUIRE_SHARED_DATA("hdri/" + hdri);
    const Environment env(loadHdr(test::sharedData("hdri/" + hdri)).pixels);
    const PrefilteredIbl ibl(env);
    const RenderScene scene(relics::makeRelic("metal-bowl"), {});
    const CameraModel view = bowlView(scene.relicBounds(), size);
    const cv::Mat region = insideMask(scene, view);
    const auto truthOf = [&](int bounces) {
      reference::PathTracerOptions o;
      o.max_bounces = bounces;
      return reference::renderPathTraced(reference::PathTracer(scene, env, o), view, spp);
    };
    const cv::Mat truth5 = truthOf(5), truth16 = truthOf(16), truth1 = truthOf(1), truth2 = truthOf(2);
    const double mean5 = regionError(truth5, truth16, region).mean_ours,
                 mean1 = regionError(truth1, truth16, region).mean_ours,
                 mean2 = regionError(truth2, truth16, region).mean_ours;
    std::printf(
        "%s metal bowl %dpx: truth 5 bounces / 16: %.4f; light of 1 bounce %.4f, of 2 %.4f, of 3 to 5 "
        "%.4f\n",
        hdri.c_str(), cv::countNonZero(region), mean5 / regionError(truth16, truth5, region).mean_ours, mean1,
        mean2 - mean1, mean5 - mean2);
    const auto [centres, one_bounce, earlier] = metalBowlSuspects();
    TracerSettings strata8;
    strata8.rough_interreflection_grid = 8;
    TracerSettings strata2;
    strata2.rough_interreflection_grid = 2;
    TracerSettings strata8_each = strata8;  // every sample traces all 64: 256 per pixel
    strata8_each.evaluation.rough_interreflection_interleaved = false;
    TracerSettings count;
    count.evaluation.lobe_visibility = false;
    TracerSettings unfiltered;
    unfiltered.evaluation.axis_aligned_filter = false;
    for (const auto& [name, settings] :
         std::vector<std::pair<std::string, TracerSettings>>{{"default", {}},
                                                             {"strata centres", centres},
                                                             {"1 mirror bounce", one_bounce},
                                                             {"centres, 1 bounce", earlier},
                                                             {"strata 8x8", strata8},
                                                             {"strata 2x2", strata2},
                                                             {"strata 8x8 each sample", strata8_each},
                                                             {"hall share by count", count},
                                                             {"filter off", unfiltered}}) {
      const cv::Mat ours = renderOurs(scene, ibl, view, settings).hdr;
      const RegionError e5 = regionError(ours, truth5, region);
      std::printf("  ours %-24s mean / truth(5) %.4f, / truth(16) %.4f; rmse %.5f\n", name.c_str(),
                  e5.meanRatio(), regionError(ours, truth16, region).meanRatio(), e5.rmse);
    }
    // The cost at a face view's default size: process CPU time of a view's render (building the
    // renderer apart) and its interreflection rays, the defaults and the earlier choice
    // alternated, medians of 5.
    const CameraModel face = bowlView(scene.relicBounds(), 320);
    std::vector<double> cpu[2];
    std::uint64_t rays[2] = {0, 0};
    for (int k = 0; k < 10; ++k) {
      FrameRenderer renderer(scene, ibl, k % 2 ? earlier : TracerSettings{});
      const std::clock_t start = std::clock();
      const FrameResult frame = renderer.render({}, {}, {face});
      cpu[k % 2].push_back(double(std::clock() - start) * 1000.0 / CLOCKS_PER_SEC);
      rays[k % 2] = frame.views.at(0).interreflection_rays;
    }
    for (auto& c : cpu) std::sort(c.begin(), c.end());
    std::printf(
        "  320x320 view: %.1f ms CPU, %llu interreflection rays (default); %.1f ms, %llu (centres, 1 "
        "bounce)\n",
        cpu[0][2], (unsigned long long)rays[0], cpu[1][2], (unsigned long long)rays[1]);
  }
}

}  // namespace
}  // namespace holo::reflect
