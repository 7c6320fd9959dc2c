// Per-camera time of each foreground stage at 640x360 on the synthetic moving-disc sequence
// (bar: the whole per-camera step, BM_PipelineOneCamera/1, at most 3.0 ms CPU on one core; run it
// under `taskset -c 0`). docs/depthfilter.md "Speed" splits the whole step by stage with perf.
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/depthfilter/border_expansion.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "holo/depthfilter/mask_depth_growth.hpp"
#include "holo/depthfilter/mask_persistence.hpp"
#include "holo/depthfilter/other_camera_witness.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "synthetic_rgbd.hpp"

namespace {

using namespace holo;
using namespace holo::depthfilter;

test::SyntheticScene scene640() {
  test::SyntheticScene scene;
  scene.width = 640;
  scene.height = 360;
  scene.focal = 500.0f;
  scene.box = {80, 100, 120, 160};
  scene.disc_radius_px = 56.0f;
  return scene;
}

const std::vector<test::SyntheticFrame>& frames() {
  static const std::vector<test::SyntheticFrame> sequence = [] {
    std::vector<test::SyntheticFrame> out;
    const test::SyntheticScene scene = scene640();
    for (int t = 0; t < 16; ++t) out.push_back(scene.render(t, 5));
    return out;
  }();
  return sequence;
}

// Arg: the mask's growth into unknown background on (1, the default) or off (0).
void BM_Mask(benchmark::State& state) {
  ForegroundMaskConfig config;
  if (state.range(0) == 0) config.unknown_background_growth_steps = 0;
  ForegroundMasker masker(config);
  for (int t = 0; t < 4; ++t) masker.learnBackground(frames()[std::size_t(t)].frame);
  std::size_t t = 0;
  for (auto _ : state) benchmark::DoNotOptimize(masker.apply(frames()[t++ % frames().size()].frame));
}
BENCHMARK(BM_Mask)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The mask's growth into readings of unknown background depth at its default steps, in its worst
// case: no background depth known anywhere, the disc's mask eroded by the steps so that every step
// grows along the disc's surface. Arg 0: growth off (its floor).
void BM_MaskDepthGrowth(benchmark::State& state) {
  MaskDepthGrowthConfig config;
  config.steps = state.range(0) != 0 ? ForegroundMaskConfig{}.unknown_background_growth_steps : 0;
  const test::SyntheticFrame& f = frames()[3];
  const cv::Mat unknown = cv::Mat::zeros(f.frame.depth.size(), CV_32FC1);
  cv::Mat seed, mask, scratch;
  cv::erode(f.disc_mask, seed, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(33, 33)));
  for (auto _ : state) {
    seed.copyTo(mask);
    growMaskIntoUnknownBackground(mask, f.frame.depth, unknown, config, scratch);
    benchmark::DoNotOptimize(mask.data);
  }
}
BENCHMARK(BM_MaskDepthGrowth)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// Args: DIS preset, downscale (the default is ULTRAFAST on half-size frames).
void BM_Flow(benchmark::State& state) {
  PrecursorFlow flow({static_cast<int>(state.range(0)), static_cast<int>(state.range(1))});
  std::size_t t = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(flow.compute(frames()[t % frames().size()].frame.colour,
                                          frames()[(t - 1) % frames().size()].frame.colour));
    ++t;
  }
}
BENCHMARK(BM_Flow)
    ->Args({cv::DISOpticalFlow::PRESET_ULTRAFAST, 2})
    ->Args({cv::DISOpticalFlow::PRESET_ULTRAFAST, 1})
    ->Args({cv::DISOpticalFlow::PRESET_FAST, 1})
    ->Args({cv::DISOpticalFlow::PRESET_MEDIUM, 1})
    ->Unit(benchmark::kMillisecond);

// Arg: mask_box_only (1, the default: the passes work on the mask's box; 0: the whole frame).
void BM_TemporalFilter(benchmark::State& state) {
  TemporalDepthFilterConfig config;
  config.learning_frames = 4;
  config.mask_box_only = state.range(0) != 0;
  TemporalDepthFilter filter(config);
  PrecursorFlow flow;
  std::vector<cv::Mat> flows;
  for (std::size_t t = 0; t < frames().size(); ++t)
    flows.push_back(flow.compute(frames()[t].frame.colour, t > 0 ? frames()[t - 1].frame.colour : cv::Mat()));
  std::size_t t = 0;
  for (; t < 6; ++t)
    filter.apply({frames()[t].frame.colour, frames()[t].frame.depth, frames()[t].true_mask, flows[t]});
  for (auto _ : state) {
    const std::size_t i = t++ % frames().size();
    benchmark::DoNotOptimize(
        filter.apply({frames()[i].frame.colour, frames()[i].frame.depth, frames()[i].true_mask, flows[i]}));
  }
}
BENCHMARK(BM_TemporalFilter)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The mask's persistence on the true masks with a zero flow (every pixel is its own precursor).
void BM_MaskPersistence(benchmark::State& state) {
  MaskPersistence persistence;
  const cv::Mat flow = cv::Mat::zeros(frames()[0].frame.depth.size(), CV_32FC2);
  std::size_t t = 0;
  cv::Mat mask;
  for (auto _ : state) {
    const test::SyntheticFrame& f = frames()[t++ % frames().size()];
    f.true_mask.copyTo(mask);
    persistence.extend(mask, f.frame, flow);
    benchmark::DoNotOptimize(mask.data);
  }
}
BENCHMARK(BM_MaskPersistence)->Unit(benchmark::kMillisecond);

void BM_BorderExpansion(benchmark::State& state) {
  const test::SyntheticFrame& f = frames()[8];
  for (auto _ : state) benchmark::DoNotOptimize(expandBorder(f.true_mask, f.true_depth, {}));
}
BENCHMARK(BM_BorderExpansion)->Unit(benchmark::kMillisecond);

// The whole per-camera step (mask, flow, mask persistence, filter, border, back-projection) on
// one core at the foreground's resolution divided by `scale` (ForegroundPipelineConfig::scale).
void runPipelineOneCamera(benchmark::State& state, int persistence, int scale,
                          bool full_size_outline = false) {
  const test::SyntheticScene scene = scene640();
  ForegroundPipelineConfig config;
  config.parallel = false;
  config.persistence.enabled = persistence != 0;
  config.flow.round_trip_check = persistence == 2;
  config.filter.learning_frames = 4;
  config.scale = scale;
  config.full_size_outline = full_size_outline;
  ForegroundPipeline pipeline({CameraModel(scene.intrinsics(), mat4(1.0f))}, config);
  test::SyntheticScene empty = scene;
  empty.objects = false;
  for (int t = 0; t < 4; ++t) {
    const RgbdFrame background = empty.render(t, 9).frame;
    pipeline.learnBackground({&background, 1});
  }
  std::size_t t = 0;
  for (; t < 6; ++t) pipeline.process({&frames()[t].frame, 1});
  for (auto _ : state)
    benchmark::DoNotOptimize(pipeline.process({&frames()[t++ % frames().size()].frame, 1}));
}

// At the default foreground scale; argument 0 switches the mask's persistence off (its cost), 2 adds
// the precursor flow's forward-backward check (its cost).
void BM_PipelineOneCamera(benchmark::State& state) {
  runPipelineOneCamera(state, int(state.range(0)), ForegroundPipelineConfig{}.scale);
}
BENCHMARK(BM_PipelineOneCamera)->Arg(1)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

// The default step (persistence on) with the foreground at the camera's resolution divided by the
// argument (1: 640x360, 2: 320x180).
void BM_PipelineOneCameraAtScale(benchmark::State& state) {
  runPipelineOneCamera(state, 1, int(state.range(0)));
}
BENCHMARK(BM_PipelineOneCameraAtScale)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The step at half resolution with the outline, depth, border and points at the camera's
// (ForegroundPipelineConfig::full_size_outline).
void BM_PipelineOneCameraAtScaleWithFullSizeOutline(benchmark::State& state) {
  runPipelineOneCamera(state, 1, 2, true);
}
BENCHMARK(BM_PipelineOneCameraAtScaleWithFullSizeOutline)->Unit(benchmark::kMillisecond);

// The cameras filling each other (the combining step between the per-camera masks and filters)
// for four cameras on one core, each seeing the sequence's frame with a sixth of its pixels
// dropped, posed 15 degrees apart so that every camera's foreground lands in the others'
// images; per camera it costs a quarter of this. Argument 0: the step disabled (its floor).
void BM_CrossCameraFill(benchmark::State& state) {
  const test::SyntheticScene scene = scene640();
  const test::SyntheticFrame& f = frames()[8];
  std::vector<CameraModel> cameras;
  std::vector<cv::Mat> depth, masks;
  for (int i = 0; i < 4; ++i) {
    const float a = 0.26f * float(i);
    const vec3 eye(2.0f * std::sin(a), 0.0f, 2.0f - 2.0f * std::cos(a));
    cameras.emplace_back(scene.intrinsics(), lookAtCameraToWorld(eye, vec3(0.0f, 0.0f, 2.0f)));
    cv::Mat d = f.frame.depth.clone();
    for (int y = i; y < d.rows; y += 6) d.row(y).setTo(0.0f);
    depth.push_back(d);
    masks.push_back(f.true_mask.clone());
  }
  CrossCameraFillConfig config;
  config.enabled = state.range(0) != 0;
  const CrossCameraFill fill(cameras, config);
  std::vector<CrossCameraView> views(4);
  for (auto _ : state) {
    for (std::size_t i = 0; i < 4; ++i) views[i] = {depth[i], masks[i].clone(), cv::Mat()};
    benchmark::DoNotOptimize(fill.apply(views));
  }
}
BENCHMARK(BM_CrossCameraFill)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The filter of camera 0 of BM_CrossCameraFill's four cameras (the sequence's frame, a sixth of
// each camera's rows dropped, 15 degrees apart), with the other three as the witness of its
// holes between two surfaces (argument 1) or without (0): the witness's cost in the per-camera
// step, the worst case of every camera's foreground landing in the others' images (each
// camera sees the same frame: a cost, not an accuracy figure).
void BM_FilterWithWitness(benchmark::State& state) {
  const test::SyntheticScene scene = scene640();
  std::vector<CameraModel> cameras;
  for (int i = 0; i < 4; ++i) {
    const float a = 0.26f * float(i);
    const vec3 eye(2.0f * std::sin(a), 0.0f, 2.0f - 2.0f * std::cos(a));
    cameras.emplace_back(scene.intrinsics(), lookAtCameraToWorld(eye, vec3(0.0f, 0.0f, 2.0f)));
  }
  const OtherCameraWitnesses witnesses(cameras);
  std::vector<std::vector<CrossCameraView>> frame_views;
  for (const test::SyntheticFrame& f : frames()) {
    frame_views.emplace_back();
    for (int i = 0; i < 4; ++i) {
      cv::Mat d = f.frame.depth.clone();
      for (int y = i; y < d.rows; y += 6) d.row(y).setTo(0.0f);
      frame_views.back().push_back({d, f.true_mask, cv::Mat()});
    }
  }
  TemporalDepthFilterConfig config;
  config.learning_frames = 4;
  TemporalDepthFilter filter(config);
  const cv::Mat flow = cv::Mat::zeros(frames()[0].frame.depth.size(), CV_32FC2);
  std::size_t t = 0;
  for (auto _ : state) {
    const std::size_t i = t++ % frames().size();
    const test::SyntheticFrame& f = frames()[i];
    const OtherCameraWitness witness = witnesses.witnessFor(frame_views[i], 0);
    benchmark::DoNotOptimize(filter.apply({f.frame.colour, frame_views[i][0].depth, f.true_mask, flow,
                                           state.range(0) != 0 ? &witness : nullptr}));
  }
}
BENCHMARK(BM_FilterWithWitness)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

}  // namespace
