#include "holo/eval/scaling_benchmark.hpp"

#include <fmt/format.h>
#include <malloc.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <stdexcept>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/log.hpp"
#include "holo/eval/frame_benchmark.hpp"
#include "holo/eval/loglog_plot.hpp"

namespace holo::eval {

namespace {

namespace fs = std::filesystem;

constexpr double kBudgetMs = 1000.0 / 30.0;

// The process's resident high-water mark restarts at its current size (Linux clear_refs 5), after
// freed memory went back to the system, so the next run's peak is its own.
void resetPeakMemory() {
  ::malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

double peakMemoryMib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  return 0.0;
}

// Every triangle split in four at its edges' midpoints, `levels` times: the same surface with
// 4^levels as many triangles (attributes interpolated; tangents recomputed from them).
TriangleMesh splitTriangles(const TriangleMesh& mesh, int levels) {
  TriangleMesh out = mesh;
  for (int level = 0; level < levels; ++level) {
    TriangleMesh next;
    next.name = out.name;
    next.material = out.material;
    const auto mid = [](const auto& a, const auto& b) { return 0.5f * (a + b); };
    for (const uvec3& t : out.triangles) {
      const std::array<std::uint32_t, 3> v{t.x, t.y, t.z};
      const auto base = static_cast<std::uint32_t>(next.positions.size());
      // The three corners, then the midpoints of edges 01, 12, 20.
      const auto add = [&](auto&& attribute) {
        for (int k = 0; k < 3; ++k) attribute(v[std::size_t(k)], v[std::size_t(k)]);
        for (int k = 0; k < 3; ++k) attribute(v[std::size_t(k)], v[std::size_t((k + 1) % 3)]);
      };
      add([&](std::uint32_t a, std::uint32_t b) {
        next.positions.push_back(mid(out.positions[a], out.positions[b]));
      });
      if (!out.normals.empty())
        add([&](std::uint32_t a, std::uint32_t b) {
          next.normals.push_back(glm::normalize(mid(out.normals[a], out.normals[b])));
        });
      if (!out.uvs.empty())
        add([&](std::uint32_t a, std::uint32_t b) { next.uvs.push_back(mid(out.uvs[a], out.uvs[b])); });
      if (!out.uvs1.empty())
        add([&](std::uint32_t a, std::uint32_t b) { next.uvs1.push_back(mid(out.uvs1[a], out.uvs1[b])); });
      next.triangles.push_back({base + 0, base + 3, base + 5});
      next.triangles.push_back({base + 3, base + 1, base + 4});
      next.triangles.push_back({base + 5, base + 4, base + 2});
      next.triangles.push_back({base + 3, base + 4, base + 5});
    }
    out = std::move(next);
  }
  if (out.normals.empty()) out.computeNormals();
  if (!mesh.tangents.empty()) out.computeTangents();
  return out;
}

fs::path modelFile(const ScalingOptions& options, const std::string& name) {
  const fs::path path = options.models_dir / name;
  if (!fs::exists(path))
    throw InputError("bench scaling", "--models", "a folder with " + name + " (the shared models)",
                     path.string());
  return path;
}

double mean(const std::vector<double>& values) {
  return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

struct Point {
  std::string label;
  double x = 0;
  FrameBenchOptions bench;
  int threads = 0;  // 0: TBB's default
};

// TBB's limit on worker threads (threads > 0; 0: none) while `limit` lives. One at a time: TBB
// applies the smallest of the limits alive.
void limitThreads(std::optional<tbb::global_control>& limit, int threads) {
  limit.reset();
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
}

ScalingPoint summarise(const std::string& sweep, const Point& point, const FrameBenchmark& b,
                       double peak_mib) {
  ScalingPoint out;
  out.sweep = sweep;
  out.label = point.label;
  out.x = point.x;
  out.frame_ms = b.median.total;
  out.floor_ms = b.floor_ms;
  out.peak_mib = peak_mib;
  out.frame_cpu_ms = mean(b.frame_cpu_ms);
  out.loop_thread_cpu_ms = mean(b.loop_thread_cpu_ms);
  const auto stageMean = [&](pipeline::StageCpu pipeline::FrameReport::*stage) {
    std::vector<double> loop_thread, process;
    for (const pipeline::FrameReport& r : b.reports) {
      loop_thread.push_back((r.*stage).loop_thread_ms);
      process.push_back((r.*stage).process_ms);
    }
    return pipeline::StageCpu{mean(loop_thread), mean(process)};
  };
  out.stage_cpu = {{"foreground", stageMean(&pipeline::FrameReport::foreground_cpu)},
                   {"rendering", stageMean(&pipeline::FrameReport::rendering_cpu)},
                   {"presenting", stageMean(&pipeline::FrameReport::presenting_cpu)}};
  std::vector<double> points;
  for (const pipeline::FrameReport& r : b.reports) points.push_back(static_cast<double>(r.foreground_points));
  std::sort(points.begin(), points.end());
  out.foreground_points = points.empty() ? 0.0 : points[points.size() / 2];
  HOLO_LOG_INFO(
      "bench scaling: {} {}: frame {:.1f} ms ({:.1f} ms CPU, {:.1f} on the loop's thread), floor {:.1f} ms, "
      "peak {:.0f} MiB",
      sweep, point.label, out.frame_ms, out.frame_cpu_ms, out.loop_thread_cpu_ms, out.floor_ms, out.peak_mib);
  return out;
}

ScalingPoint run(const std::string& sweep, const Point& point) {
  HOLO_LOG_INFO("bench scaling: {} {}", sweep, point.label);
  resetPeakMemory();
  std::optional<tbb::global_control> limit;
  limitThreads(limit, point.threads);
  const FrameBenchmark b = benchFrame(point.bench);
  return summarise(sweep, point, b, peakMemoryMib());
}

// The points' frames alternated in one process, one frame of each in turn, the order reversed
// every frame: the load of a shared machine drifts over minutes, and points run one after the
// other would each see a different load (as CPU time, too: other processes evict the caches).
// The peak memory is that of all the points' loops together.
std::vector<ScalingPoint> runAlternated(const std::string& sweep, const std::vector<Point>& points) {
  resetPeakMemory();
  std::optional<tbb::global_control> limit;
  std::vector<std::unique_ptr<FrameBenchRun>> runs;
  for (const Point& point : points) {
    HOLO_LOG_INFO("bench scaling: {} {}", sweep, point.label);
    limitThreads(limit, point.threads);
    runs.push_back(std::make_unique<FrameBenchRun>(point.bench));
  }
  const int frames = points.empty() ? 0 : runs.front()->frames();
  for (int i = 0; i < frames; ++i)
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const std::size_t r = i % 2 == 0 ? k : runs.size() - 1 - k;
      limitThreads(limit, points[r].threads);
      runs[r]->measureFrame();
    }
  const double peak_mib = peakMemoryMib();
  std::vector<ScalingPoint> out;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    limitThreads(limit, points[r].threads);
    out.push_back(summarise(sweep, points[r], runs[r]->finish(), peak_mib));
    runs[r].reset();  // its loop's memory
  }
  return out;
}

struct SweepAxis {
  const char* x_label;
  const char* title;
};

SweepAxis axisOf(const std::string& sweep) {
  if (sweep == "pixels") return {"pixels per view", "view pixels"};
  if (sweep == "cameras") return {"cameras", "cameras"};
  if (sweep == "triangles") return {"relic triangles", "relic triangles"};
  if (sweep == "voxels") return {"foreground points (median per frame)", "foreground"};
  return {"worker threads", "worker threads"};
}

void writePlots(const fs::path& dir, const std::string& sweep, const std::vector<ScalingPoint>& points) {
  const SweepAxis axis = axisOf(sweep);
  const auto series = [](const char* name, const char* colour, bool dashed) {
    PlotSeries s;
    s.name = name;
    s.colour = colour;
    s.joined = true;
    s.dashed = dashed;
    return s;
  };
  PlotSeries frame = series("frame (median)", "#1f77b4", false);
  PlotSeries floor = series("packet floor", "#7f7f7f", true);
  PlotSeries memory = series("peak resident memory", "#d62728", false);
  for (const ScalingPoint& p : points) {
    if (p.sweep != sweep) continue;
    frame.markers.push_back({p.x, p.frame_ms, fmt::format("{}: {:.1f} ms", p.label, p.frame_ms)});
    floor.markers.push_back({p.x, p.floor_ms, fmt::format("{}: floor {:.1f} ms", p.label, p.floor_ms)});
    memory.markers.push_back({p.x, p.peak_mib, fmt::format("{}: {:.0f} MiB", p.label, p.peak_mib)});
  }
  LogLogPlot time_plot;
  time_plot.title = fmt::format("Frame time against {}", axis.title);
  time_plot.x_label = axis.x_label;
  time_plot.y_label = "milliseconds";
  time_plot.series = {frame, floor};
  writeFileAtomically(dir / fmt::format("time_{}.svg", sweep), svgOf(time_plot));
  LogLogPlot memory_plot;
  memory_plot.title = fmt::format("Peak memory against {}", axis.title);
  memory_plot.x_label = axis.x_label;
  memory_plot.y_label = "MiB";
  memory_plot.series = {memory};
  writeFileAtomically(dir / fmt::format("memory_{}.svg", sweep), svgOf(memory_plot));
}

}  // namespace

std::optional<int> ThreadParts::coresFor(double budget_ms) const {
  if (serial_ms >= budget_ms) return std::nullopt;
  return std::max(1, static_cast<int>(std::ceil(parallel_ms / (budget_ms - serial_ms))));
}

ThreadParts threadParts(int threads, double loop_thread_cpu_ms, double process_cpu_ms) {
  if (threads < 2) throw std::invalid_argument("threadParts: needs at least 2 threads");
  const double n = threads;
  // Loop thread L = S + P / n, others O = C - L = P (n - 1) / n.
  const double others = std::max(0.0, process_cpu_ms - loop_thread_cpu_ms);
  ThreadParts parts;
  parts.parallel_ms = others * n / (n - 1.0);
  parts.serial_ms = std::max(0.0, process_cpu_ms - parts.parallel_ms);
  return parts;
}

ScalingResult benchScaling(const ScalingOptions& options) {
  for (const std::string& sweep : options.sweeps)
    if (sweep != "pixels" && sweep != "cameras" && sweep != "triangles" && sweep != "voxels" &&
        sweep != "threads")
      throw InputError("bench scaling", "--sweeps", "pixels, cameras, triangles, voxels or threads", sweep);
  fs::create_directories(options.out_dir);
  FrameBenchOptions defaults;
  defaults.frames = options.frames;
  defaults.warmup = options.warmup;
  defaults.loop.scene = options.scene;
  defaults.loop.view_size = options.view_size;
  defaults.loop.tracer.relic_interreflection = true;  // every effect on

  ScalingResult result;
  const auto wants = [&](const char* sweep) {
    return std::find(options.sweeps.begin(), options.sweeps.end(), sweep) != options.sweeps.end();
  };
  if (wants("pixels"))
    for (const int side : options.view_sizes) {
      Point p{fmt::format("{}x{}", side, side), double(side) * side, defaults, 0};
      p.bench.loop.view_size = side;
      result.points.push_back(run("pixels", p));
    }
  if (wants("cameras"))
    for (const int n : options.cameras) {
      Point p{fmt::format("{} camera{}", n, n > 1 ? "s" : ""), double(n), defaults, 0};
      p.bench.cameras = n;
      result.points.push_back(run("cameras", p));
    }
  if (wants("triangles")) {
    const fs::path small = modelFile(options, "bunny_nodraco.glb");
    const fs::path large = modelFile(options, "glmark2_bunny_mr.glb");
    Model split = loadGltf(large);
    for (TriangleMesh& mesh : split.meshes) mesh = splitTriangles(mesh, 2);
    const fs::path split_file = options.out_dir / "bunny_split16.glb";
    saveGltf(split_file, split);
    for (const fs::path& file : {small, large, split_file}) {
      const double triangles = static_cast<double>(loadGltf(file).triangleCount());
      Point p{fmt::format("{} ({:.0f}k triangles)", file.filename().string(), triangles / 1000.0), triangles,
              defaults, 0};
      p.bench.loop.relic = file.string();
      result.points.push_back(run("triangles", p));
    }
    fs::remove(split_file);  // 1.1M triangles: tens of MB, not a figure
  }
  if (wants("voxels"))
    for (const int visitors : options.visitors) {
      const fs::path scene = options.out_dir / fmt::format("visitors_{}.yaml", visitors);
      writeFileAtomically(scene, fmt::format("base: {}\nvisitors: {}\n", options.scene, visitors));
      Point p{fmt::format("{} visitors", visitors), 0.0, defaults, 0};
      p.bench.loop.scene = scene.string();
      ScalingPoint point = run("voxels", p);
      point.x = point.foreground_points;
      result.points.push_back(point);
      fs::remove(scene);
    }
  if (wants("threads")) {
    std::vector<Point> thread_points;
    for (const int threads : options.threads) {
      Point p{fmt::format("{} thread{}", threads, threads > 1 ? "s" : ""), double(threads), defaults,
              threads};
      p.bench.loop.view_size = options.threads_view_size;
      p.bench.loop.overlap = false;  // the worker would run beside TBB's limit
      thread_points.push_back(p);
    }
    for (const ScalingPoint& point : runAlternated("threads", thread_points)) {
      const int threads = static_cast<int>(point.x);
      if (threads == 1) {
        result.one_thread_ms = point.frame_ms;
        result.one_thread_cpu_ms = point.frame_cpu_ms;
      }
      if (threads == 2) {
        result.two_thread_ms = point.frame_ms;
        result.parts = threadParts(2, point.loop_thread_cpu_ms, point.frame_cpu_ms);
        result.cores_for_30fps = result.parts->coresFor(kBudgetMs);
        for (const auto& [stage, cpu] : point.stage_cpu)
          result.stage_parts.emplace_back(stage, threadParts(2, cpu.loop_thread_ms, cpu.process_ms));
      }
      result.points.push_back(point);
    }
  }

  nlohmann::json j;
  for (const ScalingPoint& p : result.points)
    j["points"].push_back({{"sweep", p.sweep},
                           {"label", p.label},
                           {"x", p.x},
                           {"frame_ms", p.frame_ms},
                           {"floor_ms", p.floor_ms},
                           {"peak_mib", p.peak_mib},
                           {"frame_cpu_ms", p.frame_cpu_ms},
                           {"loop_thread_cpu_ms", p.loop_thread_cpu_ms},
                           {"foreground_points", p.foreground_points}});
  if (result.one_thread_ms && result.parts) {
    j["threads_view_size"] = options.threads_view_size;
    j["one_thread_ms"] = *result.one_thread_ms;
    j["two_thread_ms"] = *result.two_thread_ms;
    j["wall_speedup"] = result.wallSpeedup();
    j["one_thread_cpu_ms"] = *result.one_thread_cpu_ms;
    j["serial_cpu_ms"] = result.parts->serial_ms;
    j["parallel_cpu_ms"] = result.parts->parallel_ms;
    j["expected_speedup"] = result.expectedSpeedup();
    for (const auto& [stage, parts] : result.stage_parts)
      j["stage_parts"][stage] = {{"serial_cpu_ms", parts.serial_ms}, {"parallel_cpu_ms", parts.parallel_ms}};
    j["cores_for_30fps"] =
        result.cores_for_30fps ? nlohmann::json(*result.cores_for_30fps) : nlohmann::json();
  }
  j["frames"] = options.frames;
  j["warmup"] = options.warmup;
  j["scene"] = options.scene;
  writeFileAtomically(options.out_dir / "scaling.json", j.dump(2));
  for (const std::string& sweep : options.sweeps) writePlots(options.out_dir, sweep, result.points);
  return result;
}

}  // namespace holo::eval
