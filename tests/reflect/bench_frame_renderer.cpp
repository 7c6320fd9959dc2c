// Per-view time of each pass of the frame renderer (milliseconds, as counters), with and without
// foreground: a mirror-like sphere (roughness 0.2), three synthetic visitors around the pyramid
// seen by four 640x360 cameras, one 256x256 face view with 4 sub-samples per pixel; one camera's
// foreground pyramid alone for masks of several sizes; the rough foreground map's build.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"
#include "synthetic_foreground.hpp"

namespace {

using namespace holo;
using namespace holo::reflect;

void frame(benchmark::State& state) {
  const bool with_foreground = state.range(0) != 0;
  const int aa = int(state.range(1));
  const RenderScene scene(
      holo::test::sphereModel({vec3(0.9f), 1.0f, 0.2f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f)), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{6, 32, 16});
  std::vector<ForegroundCameraImage> cameras;
  for (int f = 0; f < 4; ++f) {
    ForegroundCameraImage c;
    c.camera = lookAtCamera(vec3(0.0f, 0.2f, 0.0f) + 0.3f * faceDirection(f),
                            vec3(0.0f, 0.5f, 0.0f) + 2.0f * faceDirection(f), 70.0f, 640, 360);
    c.colour_bgr = cv::Mat(360, 640, CV_32FC3, cv::Scalar(0.2, 0.4, 0.8));
    c.mask = cv::Mat(360, 640, CV_32FC1, cv::Scalar(1));
    cameras.push_back(c);
  }
  depthfilter::ForegroundCloud cloud;
  if (with_foreground) cloud = holo::test::visitorCloud(3, 0.7f, 5);
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.6f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 14.0f, 256, 256);
  TracerSettings settings;
  settings.aa_samples = aa;
  FrameRenderer renderer(scene, ibl, settings);
  std::map<std::string, double> ms;
  double walked = 0.0;
  for (auto _ : state) {
    const FrameResult r = renderer.render(cloud, cameras, {view});
    for (const PassTiming& t : r.frame_timings) ms[passName(t.pass)] += t.ms;
    for (const PassTiming& t : r.views.at(0).timings) ms[passName(t.pass)] += t.ms;
    walked += double(r.views.at(0).walked_rays);
  }
  for (const auto& [name, total] : ms) state.counters[name + "_ms"] = total / double(state.iterations());
  state.counters["walked_rays"] = walked / double(state.iterations());
}
BENCHMARK(frame)
    ->ArgNames({"foreground", "aa"})
    ->Args({1, 4})
    ->Args({0, 4})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

// One camera's 7-level pyramid rebuilt per frame (the Pyramids pass per camera) for a mask that
// covers a centred box of `coverage` percent of a 640x360 image: the build is restricted to the
// mask's box grown by the blur, so a visitor covering a part of the image costs a part.
void pyramid(benchmark::State& state) {
  const double side = std::sqrt(double(state.range(0)) / 100.0);
  const cv::Size box_size(int(640 * side), int(360 * side));
  const cv::Mat colour(360, 640, CV_32FC3, cv::Scalar(0.2, 0.4, 0.8));
  cv::Mat mask(360, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect((640 - box_size.width) / 2, (360 - box_size.height) / 2, box_size.width, box_size.height))
      .setTo(255);
  ForegroundPyramid pyramid;
  for (auto _ : state) {
    pyramid.build(colour, mask, TracerSettings{}.pyramid_levels);
    benchmark::DoNotOptimize(pyramid.mask(0).data);
  }
}
BENCHMARK(pyramid)
    ->ArgName("coverage_percent")
    ->Arg(100)
    ->Arg(25)
    ->Arg(5)
    ->Arg(0)
    ->Unit(benchmark::kMicrosecond);

// The rough foreground map's per-frame build (splat + prefilter for one roughness) for the three
// synthetic visitors, at map widths 32, 64 (the default) and 128: the RoughForegroundMap pass.
void roughMap(benchmark::State& state) {
  VoxelGrid grid;
  grid.build(holo::test::visitorCloud(3, 0.7f, 5));
  RoughForegroundMap map(int(state.range(0)), {0.6f});
  for (auto _ : state) {
    map.build(grid, vec3(0.0f, 0.3f, 0.0f));
    benchmark::DoNotOptimize(map.coveredTexels());
  }
  state.counters["covered_texels"] = double(map.coveredTexels());
}
BENCHMARK(roughMap)->ArgName("width")->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

}  // namespace
