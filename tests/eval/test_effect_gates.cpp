// The effect plan's "below one displayed code" gates (effect_plan.hpp) for the visitors' light,
// the axis-aligned filter and progressive refinement, on the window scene: each effect runs where
// its estimated largest displayed change reaches TracerSettings::effect_min_codes (1) and is left
// off where it does not. Each gate is tested as SelfOcclusion.PlanLeavesItOffBelowOneDisplayedCode
// tests the self-occlusion's: in the scene's own light it is estimated above a code and runs; in
// the same hall dimmed at the exposure the bright hall fixed (a frame loop's evening) it is estimated
// below a code and does none of its work (counters), while forcing it on (effect_min_codes 0)
// changes some pixel's radiance by more than a tenth, yet no displayed pixel by a code: so leaving
// it off there cannot pass by doing nothing. The filter's second gate, its own displayed change
// where it last ran (lobe_effect_gate.hpp), on two scenes of `bench accuracy --effects`: off after
// the kettle's first frame, on at every frame of the metal bowl, checked again when the eye moves;
// progressive refinement's second gate, what its first 8 sets changed: off at the window hall's
// dusk, on with the gallery's metal bowl, checked again when the exposure rises or the eye moves.
// Also: an opaque convex relic's frames do none of the five light effects' work (counters). 24^2
// and 32^2 views, a few seconds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/image.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"

namespace holo::eval {
namespace {

// The hall and the visitors this many times darker: the gates' evening.
constexpr float kEvening = 1e-5f;

const ReflectionScene& windowScene() {
  static const ReflectionScene scene = [] {
    SceneOptions options;
    options.scene = "window";
    return loadReflectionScene(options);
  }();
  return scene;
}

// The window scene's hall as the live renderer reads it, scaled.
std::shared_ptr<const reflect::PrefilteredIbl> hallIbl(float scale) {
  const ReflectionScene& scene = windowScene();
  const reflect::Environment env(scene.panorama * double(scale), 0.0f, scene.panorama_proxy);
  return std::make_shared<const reflect::PrefilteredIbl>(env, reflect::PrefilterOptions{6, 32, 16});
}

depthfilter::ForegroundCloud visitors(float scale) {
  depthfilter::ForegroundCloud cloud = windowScene().foreground;
  for (depthfilter::ForegroundPoint& p : cloud.points) p.radiance *= scale;
  return cloud;
}

CameraModel faceView(int size) {
  ViewOptions view;
  view.width = view.height = size;
  return viewCamera(view, windowScene());
}

// CI's size: 16 visibility rays per vertex (the Lambert bowl's self-occlusion is not what is tested).
reflect::TracerSettings ciTracer() {
  reflect::TracerSettings s;
  s.self_occlusion_rays = 16;
  return s;
}

struct Change {
  float radiance = 0.0f;  // the largest change of a pixel's channel, as a share of the larger value
  float codes = 0.0f;     // the largest change of a displayed code
};

Change change(const cv::Mat& a, const cv::Mat& b, float exposure) {
  Change c;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const vec3 ra = rgbAt(a, x, y), rb = rgbAt(b, x, y);
      const float larger = std::max(maxComponent(ra), maxComponent(rb));
      if (larger > 0.0f) c.radiance = std::max(c.radiance, maxComponent(glm::abs(ra - rb)) / larger);
      c.codes = std::max(c.codes, maxComponent(glm::abs(reflect::toneMapCodes(ra, exposure) -
                                                        reflect::toneMapCodes(rb, exposure))));
    }
  return c;
}

// The exposure a view of the scene's own light chooses for itself (what a frame loop fixes).
float brightExposure(const reflect::RenderScene& relic, const reflect::PrefilteredIbl& ibl,
                     const depthfilter::ForegroundCloud& cloud, const CameraModel& view) {
  reflect::FrameRenderer renderer(relic, ibl, ciTracer());
  return renderer.render(cloud, windowScene().foreground_cameras, {view}).views.at(0).exposure;
}

TEST(EffectGates, PlanWeighsTheVisitorsLightInCodes) {
  reflect::EffectInputs in;
  in.relic_glossy = false;
  in.relic_lit_diffusely = true;
  in.visitor_within_light_distance = true;
  in.foreground_points = 100;
  in.cameras = 4;
  in.relic_bounds = {vec3(-0.1f), vec3(0.1f)};
  in.foreground_bounds = {vec3(0.5f), vec3(1.0f)};
  in.visitor_light_codes = 2.0f;
  const reflect::EffectPlan on = reflect::planEffects(in);
  EXPECT_TRUE(on.has(reflect::Pass::VisitorLight)) << on.describe();
  EXPECT_EQ(on.visitor_light_reason, "visitors near the relic's diffuse light (at most 2 sRGB codes)");
  in.visitor_light_codes = 0.5f;
  const reflect::EffectPlan off = reflect::planEffects(in);
  EXPECT_FALSE(off.has(reflect::Pass::VisitorLight)) << off.describe();
  EXPECT_FALSE(off.has(reflect::Pass::VoxelGrid)) << off.describe();
  EXPECT_EQ(off.visitor_light_reason, "visitors' light not shown (at most 0.5 sRGB codes)");
  in.effect_min_codes = 0.0f;
  EXPECT_TRUE(reflect::planEffects(in).has(reflect::Pass::VisitorLight));
}

// The window scene's visitor beside its Lambert bowl.
TEST(EffectGates, VisitorsLightOffBelowOneDisplayedCode) {
  const ReflectionScene& scene = windowScene();
  const reflect::RenderScene bowl(scene.relic, {});
  const CameraModel view = faceView(32);
  const auto bright = hallIbl(1.0f);
  reflect::TracerSettings day = ciTracer();
  day.exposure = brightExposure(bowl, *bright, scene.foreground, view);
  reflect::FrameRenderer shown_renderer(bowl, *bright, day);
  const reflect::FrameResult shown =
      shown_renderer.render(scene.foreground, scene.foreground_cameras, {view});
  EXPECT_TRUE(shown.plan.has(reflect::Pass::VisitorLight)) << shown.plan.describe();
  EXPECT_NE(shown.plan.visitor_light_reason.find("sRGB codes"), std::string::npos) << shown.plan.describe();
  EXPECT_GT(shown.visitor_light_splats, 0u);
  EXPECT_GT(shown.views.at(0).visitor_lit_samples, 0u);
  reflect::TracerSettings without = day;
  without.evaluation.visitor_light = false;
  reflect::FrameRenderer without_renderer(bowl, *bright, without);
  const Change in_daylight =
      change(shown.views.at(0).hdr,
             without_renderer.render(scene.foreground, scene.foreground_cameras, {view}).views.at(0).hdr,
             day.exposure);
  std::printf("in the scene's own light the visitors change a pixel by %.0f%%, %.1f codes\n",
              double(in_daylight.radiance) * 100.0, double(in_daylight.codes));
  EXPECT_GT(in_daylight.codes, 1.0f);

  const auto dim = hallIbl(kEvening);
  const depthfilter::ForegroundCloud dim_visitors = visitors(kEvening);
  reflect::FrameRenderer gated(bowl, *dim, day);
  const reflect::FrameResult off = gated.render(dim_visitors, scene.foreground_cameras, {view});
  EXPECT_FALSE(off.plan.has(reflect::Pass::VisitorLight)) << off.plan.describe();
  EXPECT_NE(off.plan.visitor_light_reason.find("visitors' light not shown"), std::string::npos)
      << off.plan.describe();
  EXPECT_EQ(off.visitor_light_splats, 0u);
  EXPECT_EQ(off.visitor_light_texels, 0u);
  EXPECT_EQ(off.views.at(0).visitor_lit_samples, 0u);
  EXPECT_EQ(gated.visitorLight(), nullptr);

  reflect::TracerSettings forced_settings = day;
  forced_settings.effect_min_codes = 0.0f;
  reflect::FrameRenderer forced(bowl, *dim, forced_settings);
  const reflect::FrameResult on = forced.render(dim_visitors, scene.foreground_cameras, {view});
  ASSERT_TRUE(on.plan.has(reflect::Pass::VisitorLight)) << on.plan.describe();
  EXPECT_GT(on.views.at(0).visitor_lit_samples, 0u);
  const Change c = change(off.views.at(0).hdr, on.views.at(0).hdr, day.exposure);
  std::printf("bright: %s\nevening: %s\nforced on: largest radiance change %.0f%%, %.3f codes\n",
              shown.plan.visitor_light_reason.c_str(), off.plan.visitor_light_reason.c_str(),
              double(c.radiance) * 100.0, double(c.codes));
  EXPECT_GT(c.radiance, 0.1f);  // the visitor's shadow and colour
  EXPECT_LT(c.codes, 1.0f);
}

// The metal bowl (roughness 0.4) in the window scene's hall, the foreground switched off (the
// lobe's gates are what is tested). `frames` still frames; the last one's result.
reflect::FrameResult stillFrames(const reflect::PrefilteredIbl& ibl, const reflect::TracerSettings& settings,
                                 int frames) {
  static const reflect::RenderScene metal(relics::makeRelic("metal-bowl"), {});
  reflect::FrameRenderer renderer(metal, ibl, settings);
  reflect::FrameResult last;
  for (int f = 0; f < frames; ++f) {
    last = renderer.render({}, {}, {faceView(24)});
    if (f > 0) {
      EXPECT_EQ(last.views.at(0).refinement_samples > 0, last.plan.has(reflect::Pass::ProgressiveRefinement));
    }
  }
  return last;
}

float metalExposure(const reflect::PrefilteredIbl& ibl) {
  const reflect::RenderScene metal(relics::makeRelic("metal-bowl"), {});
  return brightExposure(metal, ibl, {}, faceView(24));
}

TEST(EffectGates, AxisAlignedFilterOffBelowOneDisplayedCode) {
  const auto bright = hallIbl(1.0f);
  reflect::TracerSettings day;
  day.exposure = metalExposure(*bright);
  const reflect::FrameResult shown = stillFrames(*bright, day, 1);
  EXPECT_TRUE(shown.plan.has(reflect::Pass::AxisAlignedFilter)) << shown.plan.describe();
  EXPECT_NE(shown.plan.material_reason.find("its noise at most"), std::string::npos) << shown.plan.describe();
  EXPECT_GT(shown.views.at(0).filter_taps, 0u);

  const auto dim = hallIbl(kEvening);
  const reflect::FrameResult off = stillFrames(*dim, day, 1);
  EXPECT_FALSE(off.plan.has(reflect::Pass::AxisAlignedFilter)) << off.plan.describe();
  EXPECT_NE(off.plan.material_reason.find("the rough lobe's noise not shown"), std::string::npos)
      << off.plan.describe();
  EXPECT_EQ(off.views.at(0).filtered_pixels, 0u);
  EXPECT_EQ(off.views.at(0).filter_taps, 0u);

  reflect::TracerSettings forced_settings = day;
  forced_settings.effect_min_codes = 0.0f;
  const reflect::FrameResult on = stillFrames(*dim, forced_settings, 1);
  ASSERT_TRUE(on.plan.has(reflect::Pass::AxisAlignedFilter)) << on.plan.describe();
  EXPECT_GT(on.views.at(0).filter_taps, 0u);
  const Change c = change(off.views.at(0).hdr, on.views.at(0).hdr, day.exposure);
  std::printf("bright: %s\nevening: %s\nforced on: largest radiance change %.0f%%, %.3f codes\n",
              shown.plan.material_reason.c_str(), off.plan.material_reason.c_str(),
              double(c.radiance) * 100.0, double(c.codes));
  // The filter is a light touch: it changes a pixel by a few percent (measured 3%), which in the
  // scene's own light moves a displayed code by most of one (0.83 at 24^2), in the evening none.
  reflect::TracerSettings unfiltered = day;
  unfiltered.evaluation.axis_aligned_filter = false;
  const Change in_daylight =
      change(shown.views.at(0).hdr, stillFrames(*bright, unfiltered, 1).views.at(0).hdr, day.exposure);
  std::printf("in the scene's own light the filter changes a pixel by %.0f%%, %.2f codes\n",
              double(in_daylight.radiance) * 100.0, double(in_daylight.codes));
  EXPECT_GT(in_daylight.codes, 0.3f);
  EXPECT_GT(c.radiance, 0.02f);
  EXPECT_LT(c.codes, 1.0f);
}

TEST(EffectGates, ProgressiveRefinementOffBelowOneDisplayedCode) {
  constexpr int kFrames = 6;
  const auto bright = hallIbl(1.0f);
  reflect::TracerSettings day;
  day.exposure = metalExposure(*bright);
  day.evaluation.axis_aligned_filter = false;  // the accumulation alone
  const reflect::FrameResult shown = stillFrames(*bright, day, kFrames);
  EXPECT_TRUE(shown.plan.has(reflect::Pass::ProgressiveRefinement)) << shown.plan.describe();
  EXPECT_NE(shown.plan.material_reason.find("their spread at most"), std::string::npos)
      << shown.plan.describe();
  EXPECT_EQ(shown.views.at(0).accumulated_sets, std::uint32_t(kFrames));

  const auto dim = hallIbl(kEvening);
  const reflect::FrameResult off = stillFrames(*dim, day, kFrames);
  EXPECT_FALSE(off.plan.has(reflect::Pass::ProgressiveRefinement)) << off.plan.describe();
  EXPECT_NE(off.plan.material_reason.find("the rough lobes' spread not shown"), std::string::npos)
      << off.plan.describe();
  EXPECT_EQ(off.views.at(0).refinement_samples, 0u);
  EXPECT_EQ(off.views.at(0).accumulated_sets, 0u);

  reflect::TracerSettings forced_settings = day;
  forced_settings.effect_min_codes = 0.0f;
  const reflect::FrameResult on = stillFrames(*dim, forced_settings, kFrames);
  ASSERT_TRUE(on.plan.has(reflect::Pass::ProgressiveRefinement)) << on.plan.describe();
  EXPECT_EQ(on.views.at(0).accumulated_sets, std::uint32_t(kFrames));
  const Change c = change(off.views.at(0).hdr, on.views.at(0).hdr, day.exposure);
  std::printf("bright: %s\nevening: %s\nforced on: largest radiance change %.0f%%, %.3f codes\n",
              shown.plan.material_reason.c_str(), off.plan.material_reason.c_str(),
              double(c.radiance) * 100.0, double(c.codes));
  EXPECT_GT(c.radiance, 0.1f);
  EXPECT_LT(c.codes, 1.0f);
}

// `camera` moved `metres` along its own x axis.
CameraModel movedEye(const CameraModel& camera, float metres) {
  CameraModel moved = camera;
  mat4 pose = camera.T_world_camera();
  pose[3] += pose[0] * metres;
  moved.setPose(pose);
  return moved;
}

// A hall of `bench accuracy --effects` with `relic` at 32^2 and its prefiltered hall, built once.
struct EffectsScene {
  VisitorScene setup;
  std::shared_ptr<const reflect::PrefilteredIbl> ibl;
  reflect::RenderScene relic;
  EffectsScene(const std::string& hall, const std::string& relic_name)
      : setup(visitorScene(hall, relic_name, -1, 0.0f, 0.0f, 32)),
        ibl(staticIbl(setup.scene, MethodSettings{})),
        relic(setup.scene.relic, {}) {}
};

const EffectsScene& effectsScene(const std::string& hall, const std::string& relic) {
  static std::map<std::string, std::unique_ptr<EffectsScene>> scenes;
  std::unique_ptr<EffectsScene>& scene = scenes[hall + ":" + relic];
  if (!scene) scene = std::make_unique<EffectsScene>(hall, relic);
  return *scene;
}

// Frames of an effects scene, its visitors in, the exposure chosen by each view as the bench's
// frames do: the filter's own change where it ran decides the next static passes.
struct GateFrames {
  const EffectsScene& scene;
  reflect::FrameRenderer renderer;
  GateFrames(const std::string& hall, const std::string& relic, float effect_min_codes)
      : scene(effectsScene(hall, relic)), renderer(scene.relic, *scene.ibl, [&] {
          reflect::TracerSettings s;
          s.effect_min_codes = effect_min_codes;
          return s;
        }()) {}
  reflect::FrameResult at(const CameraModel& eye) {
    return renderer.render(scene.setup.scene.foreground, scene.setup.scene.foreground_cameras, {eye});
  }
};

// The kettle in the room (as `bench accuracy --effects` frames it): the filter changes no
// displayed code by one in its first static pass, so the next static passes (the eye 1 mm away)
// do none of its work, and their image is within a code of the filtered one; the eye 10 cm away
// (beyond LobeEffectGate::kEyeDistance) checks it again.
TEST(EffectGates, AxisAlignedFilterOffWhereItsOwnChangeWasBelowOneCode) {
  GateFrames kettle("room", "kettle", reflect::TracerSettings{}.effect_min_codes);
  const CameraModel eye = kettle.scene.setup.camera;
  const reflect::FrameResult first = kettle.at(movedEye(eye, 0.001f));
  ASSERT_TRUE(first.plan.has(reflect::Pass::AxisAlignedFilter)) << first.plan.describe();
  EXPECT_GT(first.views.at(0).filter_taps, 0u);
  const float first_codes = first.views.at(0).filter_codes;
  std::printf("the kettle's filter changed a displayed code by at most %.3f\n", double(first_codes));
  EXPECT_GT(first_codes, 0.0f);
  EXPECT_LT(first_codes, 1.0f);

  const reflect::FrameResult next = kettle.at(eye);
  EXPECT_FALSE(next.plan.has(reflect::Pass::AxisAlignedFilter)) << next.plan.describe();
  EXPECT_NE(next.plan.material_reason.find("axis-aligned filter not shown"), std::string::npos)
      << next.plan.describe();
  EXPECT_GT(next.views.at(0).shaded_samples, 0u);  // a static pass ran, without the filter
  EXPECT_EQ(next.views.at(0).filtered_pixels, 0u);
  EXPECT_EQ(next.views.at(0).filter_taps, 0u);

  // Left off, the image is the filtered one within a code (forced on: effect_min_codes 0).
  GateFrames forced("room", "kettle", 0.0f);
  forced.at(movedEye(eye, 0.001f));
  const reflect::FrameResult filtered = forced.at(eye);
  ASSERT_TRUE(filtered.plan.has(reflect::Pass::AxisAlignedFilter)) << filtered.plan.describe();
  EXPECT_GT(filtered.views.at(0).filter_taps, 0u);
  const float exposure = next.views.at(0).exposure;
  const Change c = change(next.views.at(0).hdr, filtered.views.at(0).hdr, exposure);
  std::printf("left off: %.3f codes from the filtered image (largest radiance change %.1f%%)\n",
              double(c.codes), double(c.radiance) * 100.0);
  EXPECT_GT(c.radiance, 0.0f);  // the filter does change the pixels, by less than a code
  EXPECT_LT(c.codes, 1.0f);

  const reflect::FrameResult moved = kettle.at(movedEye(eye, 0.1f));
  EXPECT_TRUE(moved.plan.has(reflect::Pass::AxisAlignedFilter)) << moved.plan.describe();
  EXPECT_GT(moved.views.at(0).filter_taps, 0u);
}

// The metal bowl in the gallery (as `bench accuracy --effects` frames it): its filter moves a
// displayed code by more than one, so every static pass keeps filtering.
TEST(EffectGates, AxisAlignedFilterStaysOnWhereItsChangeShows) {
  GateFrames bowl("gallery", "metal-bowl", reflect::TracerSettings{}.effect_min_codes);
  const CameraModel eye = bowl.scene.setup.camera;
  for (const float metres : {0.001f, 0.0f, 0.002f}) {
    const reflect::FrameResult r = bowl.at(movedEye(eye, metres));
    EXPECT_TRUE(r.plan.has(reflect::Pass::AxisAlignedFilter)) << r.plan.describe();
    EXPECT_GT(r.views.at(0).filter_taps, 0u);
    std::printf("the metal bowl's filter changed a displayed code by at most %.3f\n",
                double(r.views.at(0).filter_codes));
    EXPECT_GE(r.views.at(0).filter_codes, 1.0f);
  }
}

// Still frames of an effects scene at `eye` after a static pass 1 mm away: the last one, and the
// one in which the view's accumulation reached ProgressiveAccumulation's measured sets (8).
struct StillFrames {
  reflect::FrameResult measured, last;
};
StillFrames stillFramesAt(GateFrames& frames, const CameraModel& eye, int count) {
  StillFrames still;
  frames.at(movedEye(eye, 0.001f));
  for (int i = 0; i < count; ++i) {
    still.last = frames.at(eye);
    if (still.last.views.at(0).refinement_codes > 0.0f) still.measured = still.last;
  }
  return still;
}

// The metal bowl in the window scene's hall dimmed 10,000-fold at the exposure the bright hall fixed
// (a frame loop's dusk): the lobe's spread bound still says 3 codes, so the plan refines, but what
// the first 8 sets changed is below a code: the still frames after them do none of the
// refinement's work, and their image is within a code of the image refined on (effect_min_codes 0),
// which changed some pixel's radiance by more than a tenth since set 0. A 2x brighter exposure and
// the eye 10 cm away (beyond LobeEffectGate::kExposureStep, kEyeDistance) check it again.
TEST(EffectGates, ProgressiveRefinementOffWhereItsOwnChangeWasBelowOneCode) {
  constexpr float kDusk = 1e-4f;
  constexpr int kFrames = 12;
  static const reflect::RenderScene metal(relics::makeRelic("metal-bowl"), {});
  const auto bright = hallIbl(1.0f);
  const auto dusk = hallIbl(kDusk);
  reflect::TracerSettings day;
  day.exposure = metalExposure(*bright);
  day.evaluation.axis_aligned_filter = false;  // the accumulation alone
  reflect::TracerSettings forced_settings = day;
  forced_settings.effect_min_codes = 0.0f;
  reflect::FrameRenderer gated(metal, *dusk, day), forced(metal, *dusk, forced_settings);
  const CameraModel eye = faceView(24);
  reflect::FrameResult first, measured, off, on;
  for (int f = 0; f < kFrames; ++f) {
    const reflect::FrameResult r = gated.render({}, {}, {eye});
    on = forced.render({}, {}, {eye});
    if (f == 0) first = r;
    if (r.views.at(0).refinement_codes > 0.0f) measured = r;
    off = r;
  }
  EXPECT_NE(first.plan.material_reason.find("their spread at most"), std::string::npos)
      << first.plan.describe();
  ASSERT_TRUE(measured.plan.has(reflect::Pass::ProgressiveRefinement)) << measured.plan.describe();
  EXPECT_EQ(measured.views.at(0).accumulated_sets, 8u);
  const float codes = measured.views.at(0).refinement_codes;
  EXPECT_LT(codes, 1.0f);

  EXPECT_FALSE(off.plan.has(reflect::Pass::ProgressiveRefinement)) << off.plan.describe();
  EXPECT_NE(off.plan.material_reason.find("progressive refinement not shown"), std::string::npos)
      << off.plan.describe();
  EXPECT_EQ(off.views.at(0).refinement_samples, 0u);
  EXPECT_EQ(off.views.at(0).accumulated_sets, 8u);  // the image keeps the sets it holds

  ASSERT_TRUE(on.plan.has(reflect::Pass::ProgressiveRefinement)) << on.plan.describe();
  EXPECT_GT(on.views.at(0).refinement_samples, 0u);
  EXPECT_EQ(on.views.at(0).accumulated_sets, std::uint32_t(kFrames));
  const Change refined = change(first.views.at(0).hdr, on.views.at(0).hdr, day.exposure);
  const Change left = change(off.views.at(0).hdr, on.views.at(0).hdr, day.exposure);
  std::printf(
      "dusk: %s\nrefined on: largest radiance change %.0f%% since set 0, %.3f codes; left off: %.3f codes "
      "from it\n",
      off.plan.material_reason.c_str(), double(refined.radiance) * 100.0, double(refined.codes),
      double(left.codes));
  EXPECT_GT(refined.radiance, 0.1f);
  EXPECT_LT(refined.codes, 1.0f);
  EXPECT_LT(left.codes, 1.0f);

  gated.setExposure(day.exposure * 2.0f);
  const reflect::FrameResult brighter = gated.render({}, {}, {eye});
  EXPECT_TRUE(brighter.plan.has(reflect::Pass::ProgressiveRefinement)) << brighter.plan.describe();
  EXPECT_GT(brighter.views.at(0).refinement_samples, 0u);
  gated.setExposure(day.exposure);
  const CameraModel moved_eye = movedEye(eye, 0.1f);
  const reflect::FrameResult moved = gated.render({}, {}, {moved_eye});
  EXPECT_TRUE(moved.plan.has(reflect::Pass::ProgressiveRefinement)) << moved.plan.describe();
  EXPECT_EQ(moved.views.at(0).accumulated_sets, 1u);  // restarted at set 0
  EXPECT_GT(gated.render({}, {}, {moved_eye}).views.at(0).refinement_samples, 0u);
}

// The room's kettle and the gallery's metal bowl (as `bench accuracy --effects` frames them): their
// accumulations move a displayed code by more than one, so every still frame keeps refining.
TEST(EffectGates, ProgressiveRefinementStaysOnWhereItsChangeShows) {
  for (const auto& [hall, relic] :
       {std::pair<std::string, std::string>{"room", "kettle"}, {"gallery", "metal-bowl"}}) {
    GateFrames frames(hall, relic, reflect::TracerSettings{}.effect_min_codes);
    const StillFrames still = stillFramesAt(frames, frames.scene.setup.camera, 10);
    std::printf("the %s's %s's refinement changed a displayed code by at most %.3f in 8 sets\n", hall.c_str(),
                relic.c_str(), double(still.measured.views.at(0).refinement_codes));
    EXPECT_GE(still.measured.views.at(0).refinement_codes, 1.0f) << relic;
    EXPECT_TRUE(still.last.plan.has(reflect::Pass::ProgressiveRefinement)) << still.last.plan.describe();
    EXPECT_GT(still.last.views.at(0).refinement_samples, 0u) << relic;
    EXPECT_EQ(still.last.views.at(0).accumulated_sets, 10u) << relic;
  }
}

// An opaque convex relic beside the window scene's visitor, in its own light, three still frames:
// the mirror sphere and the same sphere rough (0.5, metal: its lobe would be sampled on a concave
// relic) cast no self-occlusion, interreflection or lobe ray, splat no visitor, filter and refine
// nothing.
TEST(EffectGates, ConvexRelicDoesNoneOfTheLightEffectsWork) {
  const ReflectionScene& scene = windowScene();
  const auto ibl = hallIbl(1.0f);
  for (const bool rough : {false, true}) {
    reflect::RenderScene sphere(relics::makeRelic("sphere"), {});
    ASSERT_TRUE(sphere.relicIsConvex());
    if (rough) {
      reflect::SurfaceMaterial m;
      m.base_colour = vec3(0.9f);
      m.metallic = 1.0f;
      m.roughness = 0.5f;
      sphere.overrideRelicMaterial(m);
    }
    reflect::FrameRenderer renderer(sphere, *ibl, ciTracer());
    EXPECT_EQ(renderer.visibility(), nullptr);
    const vec3 eye = faceView(24).position();
    const Bounds3 b = sphere.relicBounds();
    const CameraModel view = reflect::lookAtCamera(eye, b.center(), reflect::framingFovDeg(eye, b), 24, 24);
    for (int frame = 0; frame < 3; ++frame) {
      const reflect::FrameResult r = renderer.render(scene.foreground, scene.foreground_cameras, {view});
      for (const reflect::Pass pass :
           {reflect::Pass::SelfOcclusion, reflect::Pass::VisitorLight, reflect::Pass::AxisAlignedFilter,
            reflect::Pass::ProgressiveRefinement})
        EXPECT_FALSE(r.plan.has(pass)) << reflect::passName(pass) << ": " << r.plan.describe();
      EXPECT_FALSE(r.plan.interreflection) << r.plan.describe();
      const reflect::ViewImages& v = r.views.at(0);
      EXPECT_EQ(v.shaded_samples > 0, frame == 0);  // later frames reuse the static shading
      EXPECT_EQ(v.occluded_samples, 0u);
      EXPECT_EQ(v.interreflected_samples, 0u);
      EXPECT_EQ(v.interreflection_rays, 0u);
      EXPECT_EQ(r.visitor_light_splats, 0u);
      EXPECT_EQ(v.visitor_lit_samples, 0u);
      EXPECT_EQ(v.filtered_pixels, 0u);
      EXPECT_EQ(v.filter_taps, 0u);
      EXPECT_EQ(v.refinement_samples, 0u);
      EXPECT_EQ(v.accumulated_sets, 0u);
    }
    EXPECT_EQ(renderer.visitorLight(), nullptr);
  }
}

}  // namespace
}  // namespace holo::eval
