// `holopyramid bench scaling`: the live frame's time, its floor and peak memory against view
// pixels, cameras, relic triangles, foreground voxels and worker threads (eval/scaling_benchmark.hpp);
// SVG plots, a JSON, and the cores 30 fps at the threads sweep's view size needs.
#include <fmt/format.h>

#include <iostream>
#include <string>

#include "command.hpp"
#include "holo/eval/scaling_benchmark.hpp"

namespace holo::app {

using namespace holo::eval;
namespace {

int runBenchScaling(const ScalingOptions& options) {
  const ScalingResult r = benchScaling(options);
  std::cout << fmt::format("{:<10} {:<34} {:>10} {:>10} {:>8} {:>10}\n", "sweep", "point", "frame ms",
                           "floor ms", "x floor", "peak MiB");
  for (const ScalingPoint& p : r.points)
    std::cout << fmt::format("{:<10} {:<34} {:>10.1f} {:>10.1f} {:>8.2f} {:>10.0f}\n", p.sweep, p.label,
                             p.frame_ms, p.floor_ms, p.floor_ms > 0 ? p.frame_ms / p.floor_ms : 0.0,
                             p.peak_mib);
  if (r.one_thread_ms && r.parts) {
    const int side = options.threads_view_size;
    std::cout << fmt::format(
        "threads at {}x{}, every effect on, no overlap: wall time 1 thread {:.1f} ms, 2 threads {:.1f} ms: "
        "{:.2f}x "
        "(on these cores, with whatever else runs on them)\n",
        side, side, *r.one_thread_ms, *r.two_thread_ms, r.wallSpeedup());
    std::cout << fmt::format(
        "CPU time: 1 thread {:.1f} ms; at 2 threads serial part {:.1f} ms, parallel part {:.1f} ms: on 2 "
        "free "
        "cores {:.1f} ms, {:.2f}x one thread\n",
        *r.one_thread_cpu_ms, r.parts->serial_ms, r.parts->parallel_ms, r.parts->onCores(2),
        r.expectedSpeedup());
    std::string by_stage;
    double stages_serial = 0, stages_parallel = 0;
    for (const auto& [stage, parts] : r.stage_parts) {
      by_stage += fmt::format("{} {:.1f} + {:.1f}, ", stage, parts.serial_ms, parts.parallel_ms);
      stages_serial += parts.serial_ms;
      stages_parallel += parts.parallel_ms;
    }
    if (!r.stage_parts.empty())
      std::cout << fmt::format("serial + parallel CPU ms by stage: {}between them {:.1f} + {:.1f}\n",
                               by_stage, r.parts->serial_ms - stages_serial,
                               r.parts->parallel_ms - stages_parallel);
    if (r.cores_for_30fps)
      std::cout << fmt::format(
          "cores for 30 fps at {}x{} with every effect on: {} (cores like this machine's)\n", side, side,
          *r.cores_for_30fps);
    else
      std::cout << fmt::format("no core count gives 30 fps at {}x{}: the serial part alone is over 33.3 ms\n",
                               side, side);
  }
  std::cout << fmt::format("wrote {} (time_*.svg, memory_*.svg, scaling.json)\n", options.out_dir.string());
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "bench scaling",
    [](CLI::App& sub) {
      auto options = std::make_shared<ScalingOptions>();
      sub.add_option("--sweeps", options->sweeps, "Any of pixels, cameras, triangles, voxels, threads")
          ->delimiter(',')
          ->capture_default_str();
      sub.add_option("--view-sizes", options->view_sizes, "Square view sides of the pixels sweep")
          ->delimiter(',')
          ->capture_default_str();
      sub.add_option("--cameras", options->cameras, "Camera counts of the cameras sweep")
          ->delimiter(',')
          ->capture_default_str();
      sub.add_option("--visitors", options->visitors, "Visitor counts of the foreground sweep")
          ->delimiter(',')
          ->capture_default_str();
      sub.add_option("--threads", options->threads, "Worker thread counts of the threads sweep")
          ->delimiter(',')
          ->capture_default_str();
      sub.add_option("--view-size", options->view_size, "View side of the other sweeps")
          ->capture_default_str();
      sub.add_option("--threads-view-size", options->threads_view_size, "View side of the threads sweep")
          ->capture_default_str();
      sub.add_option("--frames", options->frames, "Measured frames per point")->capture_default_str();
      sub.add_option("--warmup", options->warmup, "Frames run before measuring, per point")
          ->capture_default_str();
      sub.add_option("--scene", options->scene, "Built-in scene or YAML file")->capture_default_str();
      sub.add_option("--models", options->models_dir,
                     "Folder with bunny_nodraco.glb and glmark2_bunny_mr.glb")
          ->capture_default_str();
      sub.add_option("--out", options->out_dir, "Folder for the SVG plots and scaling.json")
          ->capture_default_str();
      return [options] { return runBenchScaling(*options); };
    },
    "Frame time, floor and peak memory against view pixels, cameras, triangles, foreground and threads"});

}  // namespace holo::app
