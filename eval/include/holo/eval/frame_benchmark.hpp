// `holopyramid bench frame`: whole frames of the live pipeline (frame_loop.hpp) on a simulated
// scene, and in the same run the floor docs/architecture.md sets for a frame: one primary ray per pixel of
// the four views plus one prefiltered-environment lookup at the reflected direction, nothing
// else, cast in coherent packets (the frame's ratio is against it) and one ray at a time. The frames run back
// to back, as in the product; the floor of each frame's views is measured after them, with the loop's worker
// idle. Medians from one run, milliseconds.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "holo/core/progress.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/pipeline/frame_loop.hpp"

namespace holo::eval {

struct FrameBenchOptions {
  pipeline::FrameLoopOptions loop;
  int warmup = 3;   // frames run before measuring
  int frames = 10;  // measured frames
  // Simulate every camera frame before timing and replay them: real cameras deliver their
  // frames, while simulating four costs about a frame of CPU and would compete with it.
  bool preload = true;
  // Live (loop.live): the cameras deliver at their rate on their own capture threads, frames the
  // loop is late for are dropped, and each frame's arrival-to-present latency is measured. The
  // cameras replay a loop of `live_recorded_frames` frames simulated before the run, so that
  // producing them costs the host nothing, as with real cameras.
  int live_recorded_frames = 30;
  int cameras = 0;  // the installation's first N cameras only (bench scaling); 0: all
  // Also render every measured frame with 4 samples per pixel, the interreflection bounce and no
  // reuse (untimed) and measure the displayed images' difference.
  bool reference = false;
  // Also fold every measured frame's displayed faces into one FNV-1a digest (untimed): two runs
  // show the same pictures exactly when their digests agree.
  bool digest = false;
};

struct FrameBenchmark {
  std::vector<pipeline::FrameReport> reports;  // the measured frames
  pipeline::StageTimes median;
  std::vector<std::pair<std::string, double>> passes;  // median ms per tracer pass, all views
  pipeline::CameraFrameCounts cameras;
  // The floor (docs/architecture.md), median over the frames' views: its rays cast the fastest
  // way Embree 3 offers (coherent packets of 8 over 8x8 tiles, flush-to-zero), and, for
  // comparison with earlier figures, one ray at a time.
  double floor_ms = 0;
  double single_ray_floor_ms = 0;
  std::uint64_t floor_relic_pixels = 0;  // relic pixels of the last floor frame
  // The packet floor's CPU time (all threads; the loop's worker idle), median over the frames:
  // against frame_cpu_median_ms, the frame's cost over the floor's apart from what other
  // processes take of the cores (on an idle 2-core machine close to the wall-time ratio, both
  // keeping the cores busy).
  double floor_cpu_ms = 0;
  double setup_s = 0;                // the loop's construction (and preloading), seconds
  double busy_cores = 0;             // CPU seconds of the process per wall second of the frames
  double page_faults_per_frame = 0;  // minor faults: memory freshly mapped per frame
  // Mean absolute difference in 8-bit sRGB codes against the reference, median over the frames.
  std::optional<double> error_vs_reference_codes;
  std::optional<double> error_vs_reference_max_codes;  // the same, the largest over the frames
  std::optional<std::uint64_t> display_digest;         // with FrameBenchOptions::digest
  // Over the measured frames: the frame time's 99th percentile (nearest rank) and, live, the
  // arrival-to-present latency of the oldest camera frame each shows (FrameReport), median and
  // 99th percentile. Milliseconds.
  double frame_p99_ms = 0;
  // The process's CPU time from one frame's end to the next's (all its threads: the loop, the
  // worker, the capture threads), per measured frame, and its median and 99th percentile: the
  // frame's cost and spread apart from what other processes take of the cores.
  std::vector<double> frame_cpu_ms;
  double frame_cpu_median_ms = 0, frame_cpu_p99_ms = 0;
  // The CPU time of the loop's own thread (the one calling step()) per measured frame: its serial
  // work plus its share of the parallel work (bench scaling splits the two from it).
  std::vector<double> loop_thread_cpu_ms;
  std::optional<double> latency_median_ms, latency_p99_ms;
  // Live: the median of each part of the latency over the measured frames (pipeline::LatencyParts;
  // medians of parts need not add up to the median latency).
  std::optional<pipeline::LatencyParts> latency_parts_median_ms;
  double frameOverFloor() const { return floor_ms > 0 ? median.total / floor_ms : 0.0; }
  double frameCpuOverFloorCpu() const { return floor_cpu_ms > 0 ? frame_cpu_median_ms / floor_cpu_ms : 0.0; }
};

// One `bench frame` run taken a frame at a time, so that two runs can alternate their frames in
// the same minutes (bench scaling's threads sweep): the constructor builds the loop and runs the
// warm-up, measureFrame() runs and records one measured frame, finish() measures the floors and
// gives the medians. A frame's process CPU counts from its step() to the step's end, so another
// run's frames between them are not counted; overlapped, live or without preloading (work of the
// frame runs between steps) from the last frame's end, so such runs must not alternate. Throws
// InputError as FrameLoop does for a bad scene or settings.
class FrameBenchRun {
 public:
  explicit FrameBenchRun(FrameBenchOptions options);
  ~FrameBenchRun();
  FrameBenchRun(const FrameBenchRun&) = delete;
  FrameBenchRun& operator=(const FrameBenchRun&) = delete;
  int frames() const { return options_.frames; }
  void measureFrame();
  // Once, after the measured frames.
  FrameBenchmark finish();

 private:
  FrameBenchOptions options_;
  std::unique_ptr<pipeline::FrameLoop> loop_;
  std::unique_ptr<ProgressReporter> progress_;
  FrameBenchmark result_;
  reflect::TracerSettings reference_settings_;
  std::vector<std::vector<CameraModel>> views_;  // each measured frame's, for its floor
  std::vector<double> error_codes_;
  std::uint64_t digest_ = 0;
  double cpu_start_s_ = 0, cpu_after_last_ = 0;
  long faults_start_ = 0;
  Stopwatch wall_;
};

// All of a run's frames in a row. Throws InputError as FrameLoop does for a bad scene or settings.
FrameBenchmark benchFrame(FrameBenchOptions options);

}  // namespace holo::eval
