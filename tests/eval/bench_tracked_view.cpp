// The CPU time of a live frame on the window scene (its Lambert bowl, the visitor between the
// window and the bowl) with the light effects on and off (as `bench frame --no-light-effects`),
// where one of the four 320^2 face views follows a visitor's eye: that view moves every frame, so
// its static shading is redone, while the other three are reused. The visitor shifts by 5 mm every
// frame, as a live cloud changes, so nothing refines. Process CPU time (all threads), one frame
// per iteration; counters: each pass's wall milliseconds per frame.
#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/render_scene.hpp"

namespace {

using namespace holo;

const eval::ReflectionScene& windowScene() {
  static const eval::ReflectionScene scene = [] {
    eval::SceneOptions options;
    options.scene = "window";
    return eval::loadReflectionScene(options);
  }();
  return scene;
}

// The settings `bench frame --no-light-effects` runs.
reflect::TracerSettings withoutLightEffects() {
  reflect::TracerSettings t;
  t.evaluation.self_occlusion = false;
  t.evaluation.visitor_light = false;
  t.evaluation.axis_aligned_filter = false;
  t.rough_interreflection_roughness = 2.0f;
  t.refinement_sets = 1;
  return t;
}

void trackedView(benchmark::State& state) {
  const bool effects = state.range(0) != 0;
  const bool wide_lobe_cache = state.range(1) != 0;
  const eval::ReflectionScene& scene = windowScene();
  std::vector<CameraModel> views;
  for (int face = 0; face < 4; ++face) {
    eval::ViewOptions view;
    view.width = view.height = 320;
    view.face = face;
    views.push_back(eval::viewCamera(view, scene));
  }
  eval::ViewOptions tracked_options;
  tracked_options.width = tracked_options.height = 320;
  const vec3 eye = views[0].position();
  depthfilter::ForegroundCloud shifted = scene.foreground;
  for (depthfilter::ForegroundPoint& p : shifted.points) p.position.x += 0.005f;

  eval::MethodSettings method;
  method.tracer = effects ? reflect::TracerSettings{} : withoutLightEffects();
  method.tracer.static_reuse_distance = 0.01f;  // bench frame's default
  method.tracer.evaluation.wide_lobe_cache = wide_lobe_cache;
  const auto ibl = eval::staticIbl(scene, method);
  const reflect::RenderScene relic(scene.relic, {});
  reflect::FrameRenderer renderer(relic, *ibl, method.tracer);
  // The first frame shades every view (and lights the visibility); measured frames follow.
  renderer.render(scene.foreground, scene.foreground_cameras, views);
  std::map<std::string, double> ms;
  int frame = 0;
  for (auto _ : state) {
    ++frame;
    // The eye walks 2 cm a frame along a 10-frame loop and the framing follows (field of view).
    const float step = float(frame % 10) - 4.5f;
    tracked_options.eye =
        std::to_string(eye.x + 0.02f * step) + "," + std::to_string(eye.y) + "," + std::to_string(eye.z);
    views[0] = eval::viewCamera(tracked_options, scene);
    const reflect::FrameResult r =
        renderer.render(frame % 2 ? shifted : scene.foreground, scene.foreground_cameras, views);
    for (const reflect::PassTiming& t : r.frame_timings)
      ms[std::string("frame") + reflect::passName(t.pass)] += t.ms;
    for (const reflect::ViewImages& v : r.views)
      for (const reflect::PassTiming& t : v.timings) ms[reflect::passName(t.pass)] += t.ms;
    benchmark::DoNotOptimize(r.views.back().display.data);
  }
  for (const auto& [name, total] : ms)
    if (total > 0.0) state.counters[name + "_ms"] = total / double(state.iterations());
}
BENCHMARK(trackedView)
    ->ArgNames({"effects", "wide_lobe_cache"})
    ->Args({1, 1})
    ->Args({0, 1})
    ->Args({1, 0})
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
