// Costs of the display stage per frame: presenting four 320x320 faces headless (with and
// without reading the canvas back, as recording does), the CPU reference composition, and eye
// detection on a foreground cloud of a few visitors.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>

#include "holo/display/cpu_compose.hpp"
#include "holo/display/eye_tracker.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"

namespace holo::display {
namespace {

DisplayConfig benchConfig(int side = 1080) {
  DisplayConfig config;
  config.layout = LayoutKind::Cross;
  config.output_size = {side, side};
  return config;
}

FaceImages benchFaces() {
  FaceImages faces;
  for (int f = 0; f < kFaceCount; ++f) faces[static_cast<std::size_t>(f)] = testPatternFace(f, {320, 320});
  return faces;
}

void BM_HeadlessPresent(benchmark::State& state) {
  const bool read_back = state.range(0) != 0;
  auto presenter = makeHeadlessPresenter(benchConfig(static_cast<int>(state.range(1))));
  const FaceImages faces = benchFaces();
  for (auto _ : state) {
    presenter->present(faces);
    if (read_back) benchmark::DoNotOptimize(presenter->readBack().data);
  }
}
// Canvas 960 holds four 320-pixel views at 1:1 (cross view_size 1/3).
BENCHMARK(BM_HeadlessPresent)
    ->ArgsProduct({{0, 1}, {960, 1080}})
    ->ArgNames({"read_back", "canvas"})
    ->Unit(benchmark::kMillisecond);

void BM_CpuCompose(benchmark::State& state) {
  const DisplayConfig config = benchConfig();
  const FaceImages faces = benchFaces();
  std::array<cv::Rect2f, kFaceCount> crops;
  crops.fill(cv::Rect2f(0, 0, 320, 320));
  for (auto _ : state) benchmark::DoNotOptimize(composeCanvasCpu(config, faces, crops).data);
}
BENCHMARK(BM_CpuCompose)->Unit(benchmark::kMillisecond);

// Appending one canvas to the MP4 (H.264 through FFmpeg when available).
void BM_Mp4WriteFrame(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  auto presenter = makeHeadlessPresenter(benchConfig(side));
  presenter->present(benchFaces());
  const cv::Mat canvas = presenter->readBack();
  const auto path = std::filesystem::temp_directory_path() / "holo_bench_display.mp4";
  VideoFileWriter video(path, canvas.size(), 30.0);
  for (auto _ : state) video.write(canvas);
  state.SetLabel(video.fourcc());
  // Not finished: the temporary is removed when the writer goes.
}
BENCHMARK(BM_Mp4WriteFrame)->Arg(960)->ArgName("canvas")->Unit(benchmark::kMillisecond);

void BM_EyeTrackerUpdate(benchmark::State& state) {
  // Four visitors, one per face, each 5000 points from the floor to the top of the head.
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-0.15f, 0.15f);
  std::uniform_real_distribution<float> height(-1.0f, 0.75f);
  depthfilter::ForegroundCloud cloud;
  for (int f = 0; f < kFaceCount; ++f) {
    const vec3 centre = faceNormal(f) * 1.0f;
    for (int i = 0; i < 5000; ++i) {
      depthfilter::ForegroundPoint p;
      p.position = centre + vec3(u(rng), height(rng), u(rng));
      cloud.points.push_back(p);
    }
  }
  EyeTracker tracker;
  for (auto _ : state) {
    cloud.time_s += 1.0 / 30.0;
    benchmark::DoNotOptimize(tracker.update(cloud).data());
  }
  state.counters["points"] = static_cast<double>(cloud.points.size());
}
BENCHMARK(BM_EyeTrackerUpdate)->Unit(benchmark::kMillisecond);

// The museum's hard frames: a visitor close to a face, dense (40000 points from the floor to the
// head) with a raised forearm beside the head reaching 25 cm above it, whose thin top points are
// tried first; and a face with thin posts only (no head), where every top is tried and rejected.
void BM_EyeTrackerUpdateCloseVisitorAndNoHead(benchmark::State& state) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-0.15f, 0.15f);
  std::uniform_real_distribution<float> thin(-0.03f, 0.03f);
  std::uniform_real_distribution<float> height(-1.0f, 0.75f);
  std::uniform_real_distribution<float> arm(0.3f, 1.0f);
  std::uniform_real_distribution<float> post(-1.0f, 0.6f);
  depthfilter::ForegroundCloud cloud;
  const auto add = [&](const vec3& p) {
    depthfilter::ForegroundPoint point;
    point.position = p;
    cloud.points.push_back(point);
  };
  const vec3 close = faceNormal(0) * 0.8f;
  for (int i = 0; i < 40000; ++i) add(close + vec3(u(rng), height(rng), u(rng)));
  for (int i = 0; i < 3000; ++i) add(close + vec3(0.25f + thin(rng), arm(rng), thin(rng)));
  for (int k = 0; k < 10; ++k) {
    const vec3 base = faceNormal(1) * (0.8f + 0.15f * static_cast<float>(k)) +
                      vec3(0.0f, 0.0f, 0.1f * static_cast<float>(k % 3) - 0.1f);
    for (int i = 0; i < 1200; ++i) add(base + vec3(thin(rng), post(rng), thin(rng)));
  }
  EyeTracker tracker;
  for (auto _ : state) {
    cloud.time_s += 1.0 / 30.0;
    benchmark::DoNotOptimize(tracker.update(cloud).data());
  }
  state.counters["points"] = static_cast<double>(cloud.points.size());
}
BENCHMARK(BM_EyeTrackerUpdateCloseVisitorAndNoHead)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace holo::display
