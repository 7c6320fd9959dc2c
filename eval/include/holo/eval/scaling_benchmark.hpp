// `holopyramid bench scaling`: how the live frame grows with what it is given. Each point is a
// `bench frame` run (frame_benchmark.hpp: cameras simulated before timing, the packet floor of the
// same run) with every effect on (the live tracer plus the relic's interreflection), sweeping one
// quantity from the defaults (four 640x360 cameras, the museum's visitors and vase, 320x320 views):
//  * view pixels: square views of view_sizes;
//  * cameras: the first 1..4 of the installation;
//  * relic triangles: the 5.6k and 69k bunnies of the shared models and the 69k one with every
//    triangle split in 16 (1.1M, the same surface);
//  * foreground voxels: scenes with `visitors` visitors, x = the median foreground points;
//  * worker threads: 1 and 2 (TBB's limit, the next frame's foreground not overlapped, so the
//    limit holds for the whole frame) at threads_view_size, a loop per thread count, their frames
//    alternated in one process (eval::FrameBenchRun) so that every point sees the same load.
// Peak memory is the process's resident high-water mark over the point's run (reset before it;
// the threads sweep's: both loops together).
// The frame's serial and parallel parts are measured in CPU time, which other processes on the
// cores do not inflate as they do wall time (ThreadParts): the n-thread point's loop thread does
// the serial work and its share of the parallel work, the other threads the rest. From them,
// Amdahl's law gives the time on n free cores, S + P / n, and the cores for 30 fps.
// Units: milliseconds, MiB, pixels.
#pragma once

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "holo/pipeline/frame_report.hpp"

namespace holo::eval {

struct ScalingOptions {
  std::vector<std::string> sweeps{"pixels", "cameras", "triangles", "voxels", "threads"};
  std::vector<int> view_sizes{160, 320, 540, 1080};
  std::vector<int> cameras{1, 2, 3, 4};
  std::vector<int> visitors{0, 1, 3, 6, 12};
  std::vector<int> threads{1, 2};
  int view_size = 320;          // of every sweep but pixels and threads
  int threads_view_size = 540;  // of the threads sweep
  int frames = 10, warmup = 2;  // per point
  std::string scene = "museum";
  std::filesystem::path models_dir = "../shared/data/models";  // the bunnies
  std::filesystem::path out_dir = "docs/images/scaling";       // SVGs and scaling.json
};

struct ScalingPoint {
  std::string sweep;
  double x = 0;  // view pixels (side^2), cameras, triangles, foreground points, threads
  std::string label;
  double frame_ms = 0, floor_ms = 0, peak_mib = 0;
  double foreground_points = 0;
  // CPU per frame, means over the measured frames (one frame's parts add up; medians of parts
  // need not): the whole process's and the loop thread's (FrameBenchmark).
  double frame_cpu_ms = 0, loop_thread_cpu_ms = 0;
  // The same per stage of the frame (FrameReport's foreground_cpu, rendering_cpu, presenting_cpu).
  std::vector<std::pair<std::string, pipeline::StageCpu>> stage_cpu;
};

// A frame's serial and parallel work, CPU ms, measured with `threads` > 1 worker threads (TBB's
// limit): the loop's thread spent `loop_thread_cpu_ms` (the serial part S plus its 1 / threads
// share of the parallel part P; waiting for the others' share counts where it spins), the process
// `process_cpu_ms` (S + P), so the other threads did P (threads - 1) / threads. Idle workers'
// spinning is counted in P (it is process CPU), which makes S, and the core count, optimistic by
// that much. Invariants: serial_ms, parallel_ms >= 0.
struct ThreadParts {
  double serial_ms = 0, parallel_ms = 0;
  // The frame on n free cores (Amdahl), ms.
  double onCores(int n) const { return serial_ms + parallel_ms / static_cast<double>(std::max(1, n)); }
  // The fewest cores whose frame fits budget_ms; none when the serial part alone does not.
  std::optional<int> coresFor(double budget_ms) const;
};
// Throws std::invalid_argument for threads < 2 (one thread cannot tell the parts apart).
ThreadParts threadParts(int threads, double loop_thread_cpu_ms, double process_cpu_ms);

struct ScalingResult {
  std::vector<ScalingPoint> points;
  // From the threads sweep's 1- and 2-thread frames, when both ran: their wall-time medians
  // (inflated by whatever else runs on the cores), the 1-thread frame's CPU time (its time on a
  // free core) and the parts measured at 2 threads.
  std::optional<double> one_thread_ms, two_thread_ms, one_thread_cpu_ms;
  std::optional<ThreadParts> parts;
  // `parts` per stage of the frame (foreground, rendering, presenting); the frame's parts less
  // theirs are the loop's own work between them.
  std::vector<std::pair<std::string, ThreadParts>> stage_parts;
  std::optional<int> cores_for_30fps;  // from `parts`; none: the serial part alone is over the budget
  double wallSpeedup() const {
    return one_thread_ms && two_thread_ms ? *one_thread_ms / *two_thread_ms : 0.0;
  }
  // The 1-thread frame's CPU over the frame on 2 free cores from the parts.
  double expectedSpeedup() const {
    return one_thread_cpu_ms && parts ? *one_thread_cpu_ms / parts->onCores(2) : 0.0;
  }
};

// Runs the sweeps, writes OUT/{time,memory}_<sweep>.svg and OUT/scaling.json. Throws InputError
// for an unknown sweep or a missing model file (naming it).
ScalingResult benchScaling(const ScalingOptions& options);

}  // namespace holo::eval
