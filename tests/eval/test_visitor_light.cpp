// Visitors in the hall's light (reflect/visitor_light.hpp): a visitor standing between the window
// scene's bright window and its Lambert bowl shadows the bowl and lends it colour in the
// path-traced truth; ours shows both only with the effect. The region is the truth's own: the
// pixels where the truth with the visitor differs from the truth without by more than a tenth of
// the latter (luminance, each blurred 3x3 against the truth's noise). Small in CI (40^2 views,
// 128 spp truths); the figures of docs/reflect.md come from
// `HOLO_FULL_EVAL=1 test_eval_visitor_light --gtest_filter='*Figures*'` (128^2, 1024 spp).
// Also: the irradiance change of a visitor shell all round against its closed form, and a frame
// with no visitor near (or a relic without diffuse light) doing none of the work (counters).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/image.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/visitor_light.hpp"
#include "holo/relics/relics.hpp"
#include "shared_data.hpp"

namespace holo::eval {
namespace {

cv::Mat luminanceImage(const cv::Mat& bgr) {
  cv::Mat out(bgr.rows, bgr.cols, CV_32FC1);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) out.at<float>(y, x) = luminance(rgbAt(bgr, x, y));
  return out;
}

// Where the visitor changes the truth: |L_with - L_without| > 0.1 L_without, both blurred 3x3.
cv::Mat visitorRegion(const cv::Mat& truth_with, const cv::Mat& truth_without) {
  cv::Mat with, without;
  cv::blur(luminanceImage(truth_with), with, cv::Size(3, 3));
  cv::blur(luminanceImage(truth_without), without, cv::Size(3, 3));
  cv::Mat region(with.size(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < with.rows; ++y)
    for (int x = 0; x < with.cols; ++x) {
      const float a = with.at<float>(y, x), b = without.at<float>(y, x);
      if (b > 0.0f && std::abs(a - b) > 0.1f * b) region.at<std::uint8_t>(y, x) = 1;
    }
  return region;
}

// RMSE over the region's pixels and RGB channels.
double regionRmse(const cv::Mat& ours, const cv::Mat& truth, const cv::Mat& region) {
  double sq = 0;
  int n = 0;
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x) {
      if (!region.at<std::uint8_t>(y, x)) continue;
      const vec3 d = rgbAt(ours, x, y) - rgbAt(truth, x, y);
      sq += double(glm::dot(d, d));
      n += 3;
    }
  return n > 0 ? std::sqrt(sq / n) : 0.0;
}

struct WindowFigures {
  int pixels = 0;                          // the region's
  double rmse_with = 0, rmse_without = 0;  // ours with and without the effect, over the region
  double truth_noise = 0;                  // the truth's own rmse over the region (a second seed)
  double ms_with = 0, ms_without = 0;      // medians of alternated views (cloud to image)
  double grid_ms = 0, light_ms = 0;        // medians of the VoxelGrid and VisitorLight passes (with)
  reflect::FrameResult frame;              // ours with the effect, for its plan and counters
  cv::Mat truth_with, truth_without, ours_with, ours_without, region;
};

// The window scene (face 0's default view), loaded once.
const ReflectionScene& windowScene() {
  static const ReflectionScene scene = [] {
    SceneOptions options;
    options.scene = "window";
    return loadReflectionScene(options);
  }();
  return scene;
}

// CI's size: 16 visibility rays per vertex instead of 256 (the bowl's self-occlusion is built by
// every renderer; the figures keep the defaults).
reflect::TracerSettings ciTracer() {
  reflect::TracerSettings s;
  s.self_occlusion_rays = 16;
  return s;
}

WindowFigures measureWindow(int size, int spp, int timing_repeats, bool noise,
                            const reflect::TracerSettings& tracer = {}) {
  const ReflectionScene& scene = windowScene();
  ViewOptions view;
  view.width = view.height = size;
  const CameraModel camera = viewCamera(view, scene);
  WindowFigures f;
  MethodSettings gt;
  gt.spp = spp;
  f.truth_with = renderMethod("gt", scene, camera, gt).image;
  MethodSettings empty = gt;
  empty.with_visitors = false;
  f.truth_without = renderMethod("gt", scene, camera, empty).image;
  f.region = visitorRegion(f.truth_with, f.truth_without);
  f.pixels = cv::countNonZero(f.region);

  MethodSettings ours;
  ours.tracer = tracer;
  ours.static_ibl = staticIbl(scene, ours);
  MethodSettings off = ours;
  off.tracer.evaluation.visitor_light = false;
  std::vector<double> with_ms, without_ms, grid_ms, light_ms;
  for (int r = 0; r < std::max(timing_repeats, 1); ++r) {
    const MethodResult a = renderMethod("ours", scene, camera, ours);
    const MethodResult b = renderMethod("ours", scene, camera, off);
    with_ms.push_back(a.ms);
    double grid = 0, light = 0;
    for (const auto& [pass, ms] : a.passes) {
      if (pass == reflect::passName(reflect::Pass::VoxelGrid)) grid += ms;
      if (pass == reflect::passName(reflect::Pass::VisitorLight)) light += ms;
    }
    grid_ms.push_back(grid);
    light_ms.push_back(light);
    without_ms.push_back(b.ms);
    f.ours_with = a.image;
    f.ours_without = b.image;
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  f.ms_with = median(with_ms);
  f.ms_without = median(without_ms);
  f.grid_ms = median(grid_ms);
  f.light_ms = median(light_ms);
  f.rmse_with = regionRmse(f.ours_with, f.truth_with, f.region);
  f.rmse_without = regionRmse(f.ours_without, f.truth_with, f.region);
  if (noise) {
    MethodSettings other = gt;
    other.seed = 2;
    // Half the squared difference of two truths is the variance each rmse above contains.
    f.truth_noise =
        regionRmse(renderMethod("gt", scene, camera, other).image, f.truth_with, f.region) / std::sqrt(2.0);
  }
  // The plan and counters of ours with the effect.
  const reflect::RenderScene relic(scene.relic, {});
  reflect::FrameRenderer renderer(relic, *ours.static_ibl, ours.tracer);
  f.frame = renderer.render(scene.foreground, scene.foreground_cameras, {camera});
  return f;
}

// The window scene at CI size: the region's error with the effect well below the error without.
TEST(VisitorLight, WindowSceneShadowAndColourNeedTheEffect) {
  const WindowFigures f = measureWindow(40, 128, 1, false, ciTracer());
  std::printf("window scene 40^2: region %d px, rmse with %.4f, without %.4f (%.2fx); %s\n", f.pixels,
              f.rmse_with, f.rmse_without, f.rmse_without / f.rmse_with, f.frame.plan.describe().c_str());
  ASSERT_GT(f.pixels, 40) << "the visitor changes too little of the truth";
  EXPECT_TRUE(f.frame.plan.has(reflect::Pass::VisitorLight)) << f.frame.plan.describe();
  EXPECT_GT(f.frame.views.at(0).visitor_lit_samples, 0u);
  EXPECT_GT(f.rmse_without, 2.0 * f.rmse_with);
}

// Visitors far from the relic, none at all, or near a relic with no diffuse or wide lobe: the frame
// plans no visitors' light, builds no probe and changes no sample.
TEST(VisitorLight, NoVisitorNearDoesNoWork) {
  const ReflectionScene& scene = windowScene();
  ViewOptions view;
  view.width = view.height = 24;
  const CameraModel camera = viewCamera(view, scene);
  MethodSettings settings;
  const auto ibl = staticIbl(scene, settings);
  const reflect::RenderScene bowl(scene.relic, {});

  depthfilter::ForegroundCloud far = scene.foreground;
  for (auto& p : far.points) p.position += vec3(0.0f, 0.0f, 2.0f);  // the visitor 2.8 m from the axis
  reflect::FrameRenderer renderer(bowl, *ibl, ciTracer());
  for (const depthfilter::ForegroundCloud* cloud :
       std::vector<const depthfilter::ForegroundCloud*>{&far, nullptr}) {
    const reflect::FrameResult r = cloud ? renderer.render(*cloud, scene.foreground_cameras, {camera})
                                         : renderer.render({}, {}, {camera});
    EXPECT_FALSE(r.plan.has(reflect::Pass::VisitorLight)) << r.plan.describe();
    EXPECT_FALSE(r.plan.has(reflect::Pass::VoxelGrid)) << r.plan.describe();
    EXPECT_EQ(r.visitor_light_splats, 0u);
    EXPECT_EQ(r.views.at(0).visitor_lit_samples, 0u);
    EXPECT_EQ(renderer.visitorLight(), nullptr);
  }
  // The near visitor: the work is done.
  const reflect::FrameResult near = renderer.render(scene.foreground, scene.foreground_cameras, {camera});
  EXPECT_TRUE(near.plan.has(reflect::Pass::VisitorLight)) << near.plan.describe();
  EXPECT_GT(near.visitor_light_splats, 0u);
  EXPECT_GT(near.views.at(0).visitor_lit_samples, 0u);

  // A mirror sphere (metal, smooth): its lobes are the walk's; no visitors' light.
  const reflect::RenderScene mirror(relics::makeRelic("sphere"), {});
  reflect::FrameRenderer mirror_renderer(mirror, *ibl);
  const reflect::FrameResult m = mirror_renderer.render(scene.foreground, scene.foreground_cameras, {camera});
  EXPECT_FALSE(m.plan.has(reflect::Pass::VisitorLight)) << m.plan.describe();
  EXPECT_EQ(m.visitor_light_splats, 0u);
  EXPECT_EQ(mirror_renderer.visitorLight(), nullptr);
}

// The plan alone: the visitors' light needs its switch, a relic lit diffusely and a visitor within
// reach; the voxel grid comes with it even where the walk's passes do not run.
TEST(VisitorLight, PlanWantsASwitchADiffuseRelicAndANearVisitor) {
  reflect::EffectInputs in;
  in.relic_glossy = false;
  in.relic_lit_diffusely = true;
  in.visitor_within_light_distance = true;
  in.foreground_points = 100;
  in.cameras = 4;
  in.relic_bounds = {vec3(-0.1f), vec3(0.1f)};
  in.foreground_bounds = {vec3(0.5f), vec3(1.0f)};
  const reflect::EffectPlan on = reflect::planEffects(in);
  EXPECT_TRUE(on.has(reflect::Pass::VisitorLight)) << on.describe();
  EXPECT_TRUE(on.has(reflect::Pass::VoxelGrid)) << on.describe();
  EXPECT_FALSE(on.has(reflect::Pass::ForegroundWalk)) << on.describe();
  for (const auto& [change, reason] :
       std::vector<std::pair<std::function<void(reflect::EffectInputs&)>, std::string>>{
           {[](reflect::EffectInputs& i) { i.visitor_light_enabled = false; }, "visitors' light off"},
           {[](reflect::EffectInputs& i) { i.relic_lit_diffusely = false; },
            "no diffuse or wide-lobed relic material: no visitors' light"},
           {[](reflect::EffectInputs& i) { i.foreground_points = 0; }, "no visitor to light the relic"},
           {[](reflect::EffectInputs& i) { i.visitor_within_light_distance = false; },
            "no visitor near enough to light the relic"}}) {
    reflect::EffectInputs off = in;
    change(off);
    const reflect::EffectPlan plan = reflect::planEffects(off);
    EXPECT_EQ(plan.visitor_light_reason, reason);
    EXPECT_FALSE(plan.has(reflect::Pass::VisitorLight)) << plan.describe();
    EXPECT_FALSE(plan.has(reflect::Pass::VoxelGrid)) << plan.describe();
  }
}

// A visitor shell all round the relic, of radiance Lv under a hall of uniform radiance Lh, changes
// every normal's irradiance by pi (Lv - Lh): the probes' projection and convolution are exact for
// a constant.
TEST(VisitorLight, ShellAllRoundChangesIrradianceByItsClosedForm) {
  const vec3 hall(0.8f, 0.6f, 0.4f), visitor(0.1f, 0.3f, 0.05f);
  cv::Mat pano(32, 64, CV_32FC3, cv::Scalar(hall.z, hall.y, hall.x));
  const reflect::Environment env(pano);
  const reflect::PrefilteredIbl ibl(env, reflect::PrefilterOptions{4, 16, 8});
  depthfilter::ForegroundCloud cloud;
  // Points 1 cm apart on a sphere of 0.8 m around (0, 0.15, 0).
  const vec3 centre(0.0f, 0.15f, 0.0f);
  const int rings = 250;
  for (int i = 0; i < rings; ++i) {
    const float theta = kPi * (float(i) + 0.5f) / float(rings);
    const int around = std::max(1, int(2.0f * float(rings) * std::sin(theta)));
    for (int j = 0; j < around; ++j) {
      const float phi = 2.0f * kPi * float(j) / float(around);
      depthfilter::ForegroundPoint p;
      p.position = centre + 0.8f * vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                        std::sin(theta) * std::sin(phi));
      p.radiance = visitor;
      p.weight = 1.0f;
      cloud.points.push_back(p);
    }
  }
  reflect::VoxelGrid grid;
  grid.build(cloud);
  reflect::VisitorLight light(64);
  light.build(grid, ibl, Bounds3{centre - vec3(0.1f), centre + vec3(0.1f)});
  EXPECT_GT(light.coveredTexels(), 0.99 * 8 * 64 * 32);
  for (const vec3& n : {vec3(0, 1, 0), vec3(1, 0, 0), glm::normalize(vec3(0.3f, -0.6f, 0.7f))})
    for (const vec3& p : {centre, centre + vec3(0.05f, -0.08f, 0.02f)}) {
      const vec3 change = light.irradianceChange(p, n);
      const vec3 expected = kPi * (visitor - hall);
      EXPECT_LT(glm::length(change - expected), 0.03f * glm::length(expected)) << n.x << n.y << n.z;
    }
}

// A pixel's folded response read once per frame against every sample evaluated alone (its own
// point, normal and mirror direction: irradianceChange, the definition): a 12x10 view of points
// inside the probes' box with random normals, a third of the pixels refined into four sub-samples
// 1 mm apart (one of them missing the relic), half of the materials wide-lobed, a visitor beside
// the box and a hall brighter on one side. A one-sample pixel's change is the same sum folded
// (within 1e-4 of the largest change: float rounding); the one interpolation point of a refined
// pixel (its first valid sample's) is the only approximation, within 5e-3 of the largest change
// for sub-samples 1 mm apart in a 0.3 m box. The displayed codes are written as toneMapPixel of
// the changed radiance, and nowhere else.
TEST(VisitorLight, PixelResponsesMatchEverySampleAlone) {
  cv::Mat pano(32, 64, CV_32FC3, cv::Scalar(0.2, 0.3, 0.4));
  pano(cv::Rect(8, 8, 12, 10)).setTo(cv::Scalar(3.0, 4.0, 6.0));  // a window
  const reflect::Environment env(pano);
  const reflect::PrefilteredIbl ibl(env, reflect::PrefilterOptions{4, 16, 8});
  depthfilter::ForegroundCloud cloud;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 100; ++j) {
      depthfilter::ForegroundPoint p;
      p.position = vec3(0.5f, 0.01f * float(j), -0.3f + 0.01f * float(i));
      p.radiance = vec3(0.6f, 0.2f, 0.1f);
      p.weight = 1.0f;
      cloud.points.push_back(p);
    }
  reflect::VoxelGrid grid;
  grid.build(cloud);
  const Bounds3 box{vec3(-0.15f, 0.0f, -0.15f), vec3(0.15f, 0.3f, 0.15f)};
  reflect::VisitorLight light(64);
  light.build(grid, ibl, box);
  ASSERT_GT(light.coveredTexels(), 0u);

  reflect::HitPointBuffer hits;
  hits.width = 12;
  hits.height = 10;
  const std::size_t pixels = hits.pixelCount();
  hits.hits.resize(pixels);
  hits.valid.assign(pixels, 0);
  hits.first_sub.assign(pixels, reflect::HitPointBuffer::kCentreOnly);
  std::vector<reflect::SplitSumShading> shading(pixels);
  cv::RNG rng(7);
  const auto unit = [&] {
    const vec3 v(float(rng.uniform(-1.0, 1.0)), float(rng.uniform(-1.0, 1.0)), float(rng.uniform(-1.0, 1.0)));
    return glm::normalize(v + vec3(1e-3f));
  };
  const auto sample = [&](const vec3& position, bool wide) {
    reflect::HitPoint hp;
    hp.position = position;
    hp.normal = unit();
    hp.reflected = unit();
    hp.material.roughness = wide ? 1.0f : 0.5f;
    reflect::SplitSumShading s;
    s.diffuse = vec3(0.7f, 0.5f, 0.3f) / kPi * ibl.irradiance(hp.normal);
    s.specular_scale = vec3(0.04f, 0.05f, 0.06f);
    return std::make_pair(hp, s);
  };
  for (std::size_t p = 0; p < pixels; ++p) {
    if (p % 7 == 3) continue;  // misses the relic
    const vec3 at =
        box.lo + (box.hi - box.lo) * vec3(float(rng.uniform(0.0, 1.0)), float(rng.uniform(0.0, 1.0)),
                                          float(rng.uniform(0.0, 1.0)));
    const bool wide = p % 2 == 0;
    hits.covered.push_back(std::uint32_t(p));
    if (p % 3 != 0) {
      std::tie(hits.hits[p], shading[p]) = sample(at, wide);
      hits.valid[p] = 1;
      continue;
    }
    hits.refined.push_back(std::uint32_t(p));
    hits.first_sub[p] = std::uint32_t(hits.hits.size());
    for (int k = 0; k < 4; ++k) {
      const auto [hp, s] = sample(at + vec3(0.001f * float(k), 0.0f, 0.0f), wide);
      hits.hits.push_back(hp);
      shading.push_back(s);
      hits.valid.push_back(k != 2);
    }
  }
  const reflect::VisitorLight::Receivers receivers = reflect::VisitorLight::receivers(hits, shading, ibl);
  const cv::Mat base(hits.height, hits.width, CV_32FC3, cv::Scalar::all(10.0));  // no pixel clamps
  cv::Mat hdr = base.clone();
  cv::Mat display(hits.height, hits.width, CV_8UC3, cv::Scalar::all(0));
  const float exposure = 0.05f;
  const std::uint64_t changed = light.apply(receivers, hits.width, hdr, &display, exposure);

  std::uint64_t valid_samples = 0;
  float largest = 0.0f, worst_single = 0.0f, worst_refined = 0.0f;
  for (std::uint32_t p : hits.covered) {
    vec3 expected(0.0f);
    for (std::size_t i = hits.firstSample(p); i < hits.firstSample(p) + std::size_t(hits.sampleCount(p));
         ++i) {
      if (!hits.valid[i]) continue;
      ++valid_samples;
      const reflect::HitPoint& hp = hits.hits[i];
      expected += vec3(0.7f, 0.5f, 0.3f) / kPi * light.irradianceChange(hp.position, hp.normal);
      if (hp.material.roughness >= reflect::kGlossyRoughnessLimit)
        expected += shading[i].specular_scale * light.irradianceChange(hp.position, hp.reflected) / kPi;
    }
    expected /= float(hits.sampleCount(p));
    const int x = int(p) % hits.width, y = int(p) / hits.width;
    const vec3 got = rgbAt(hdr, x, y) - rgbAt(base, x, y);
    largest = std::max(largest, maxComponent(glm::abs(expected)));
    float& worst = hits.sampleCount(p) == 1 ? worst_single : worst_refined;
    worst = std::max(worst, maxComponent(glm::abs(got - expected)));
    EXPECT_EQ(display.at<cv::Vec3b>(y, x), reflect::toneMapPixel(rgbAt(hdr, x, y), exposure)) << p;
  }
  std::printf("folded responses: largest change %.4g, worst error %.2g of it (one sample), %.2g (refined)\n",
              largest, worst_single / largest, worst_refined / largest);
  EXPECT_EQ(changed, valid_samples);
  EXPECT_GT(largest, 1e-3f) << "the visitor must change the light";
  EXPECT_LT(worst_single, 1e-4f * largest);
  EXPECT_LT(worst_refined, 5e-3f * largest);
  for (int y = 0; y < hits.height; ++y)
    for (int x = 0; x < hits.width; ++x)
      if (std::size_t(y * hits.width + x) % 7 == 3) {
        EXPECT_EQ(rgbAt(hdr, x, y), rgbAt(base, x, y));
        EXPECT_EQ(display.at<cv::Vec3b>(y, x), cv::Vec3b(0, 0, 0));
      }
}

// The figures (opt-in): 128^2 views, 1024 spp truths, the frame's extra time over 9 alternated
// renders; writes the images beside test::scratchDir("visitor_light").
TEST(VisitorLight, Figures) {
  if (!std::getenv("HOLO_FULL_EVAL")) GTEST_SKIP() << "HOLO_FULL_EVAL=1 renders the figures";
  const WindowFigures f = measureWindow(128, 1024, 9, true);
  std::printf(
      "window scene 128^2 (truth 1024 spp): region %d px; rmse with %.4f, without %.4f (%.2fx lower with); "
      "truth noise %.4f; view %.2f ms with, %.2f ms without (medians of 9 alternated); passes VoxelGrid %.2f "
      "ms, "
      "VisitorLight %.2f ms (build and apply)\n%s\n",
      f.pixels, f.rmse_with, f.rmse_without, f.rmse_without / f.rmse_with, f.truth_noise, f.ms_with,
      f.ms_without, f.grid_ms, f.light_ms, f.frame.plan.describe().c_str());
  const auto dir = test::scratchDir("visitor_light");
  const float exposure = reflect::autoExposure(f.truth_without);
  cv::Mat region_image;
  f.region.convertTo(region_image, CV_8UC1, 255.0);
  cv::Mat region_bgr;
  cv::cvtColor(region_image, region_bgr, cv::COLOR_GRAY2BGR);
  cv::Mat strip;
  cv::hconcat(std::vector<cv::Mat>{reflect::toneMap(f.truth_without, exposure),
                                   reflect::toneMap(f.truth_with, exposure), region_bgr,
                                   reflect::toneMap(f.ours_without, exposure),
                                   reflect::toneMap(f.ours_with, exposure)},
              strip);
  cv::imwrite((dir / "window_visitor_light.png").string(), strip);
  std::printf("wrote %s\n", (dir / "window_visitor_light.png").string().c_str());
  EXPECT_GT(f.rmse_without, 3.0 * f.rmse_with);
}

}  // namespace
}  // namespace holo::eval
