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
//    limit holds for the whole frame) at threads_view_size.
// Peak memory is the process's resident high-water mark over the point's run (reset before it).
// From the thread points, Amdahl's law: serial fraction s = 2 T2 / T1 - 1, and the cores n with
// T1 (s + (1 - s) / n) <= 1000 / 30 ms.
// Units: milliseconds, MiB, pixels.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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
};

struct ScalingResult {
  std::vector<ScalingPoint> points;
  // From the threads sweep's 1- and 2-thread frames, when both ran.
  std::optional<double> one_thread_ms, two_thread_ms, serial_fraction;
  std::optional<int> cores_for_30fps;  // none: the serial part alone is over the budget
  double efficiency() const {          // T1 / (2 T2)
    return one_thread_ms && two_thread_ms ? *one_thread_ms / (2.0 * *two_thread_ms) : 0.0;
  }
};

// Runs the sweeps, writes OUT/{time,memory}_<sweep>.svg and OUT/scaling.json. Throws InputError
// for an unknown sweep or a missing model file (naming it).
ScalingResult benchScaling(const ScalingOptions& options);

}  // namespace holo::eval
