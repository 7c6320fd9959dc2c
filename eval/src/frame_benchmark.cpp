#include "holo/eval/frame_benchmark.hpp"

#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <ctime>

#include "holo/core/denormals.hpp"
#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/eval/frame_timing_report.hpp"
#include "holo/reflect/view.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "replayed_source.hpp"

namespace holo::eval {

using namespace holo::pipeline;
namespace {

// One primary ray per pixel of every view against the relic and, where it hits, one
// prefiltered-IBL lookup at the mirror direction, the rays cast one at a time (rtcIntersect1).
// Returns milliseconds.
double singleRayFloorMs(const FrameLoop& loop, const std::vector<CameraModel>& views,
                        const reflect::PrefilteredIbl& ibl) {
  const Stopwatch floor_time;
  float sink = 0;
  for (const CameraModel& view : views) {
    const int w = view.width(), h = view.height();
    std::vector<float> row_sum(static_cast<std::size_t>(h), 0.0f);
    tbb::parallel_for(0, h, [&](int y) {
      float sum = 0;
      for (int x = 0; x < w; ++x) {
        const Ray ray = reflect::primaryRay(view, vec2(x + 0.5f, y + 0.5f));
        const RayHit hit = loop.renderScene().relicOnly().intersect(ray);
        if (!hit.hit()) continue;
        const vec3 n = loop.renderScene().relicOnly().shadingNormal(hit, ray.direction);
        sum += ibl.specular(glm::reflect(ray.direction, n), 0.2f).g;
      }
      row_sum[static_cast<std::size_t>(y)] = sum;
    });
    for (float s : row_sum) sink += s;
  }
  if (!std::isfinite(sink)) HOLO_LOG_WARN("single-ray floor frame produced a non-finite sum");
  return floor_time.ms();
}

// The same work the fastest way Embree 3 offers: 8x8 tiles in parallel, each cast as coherent
// packets of the CPU's native width (RayScene::intersectCoherent: four of 16 with AVX-512, else
// eight of 8), with flush-to-zero and denormals-are-zero set on the casting threads. Returns
// milliseconds; `hits`: relic pixels.
double packetFloorMs(const FrameLoop& loop, const std::vector<CameraModel>& views,
                     const reflect::PrefilteredIbl& ibl, std::uint64_t& hits) {
  constexpr int kTile = 8;
  const RayScene& relic = loop.renderScene().relicOnly();
  const Stopwatch floor_time;
  std::atomic<std::uint64_t> hit_count{0};
  float sink = 0;
  for (const CameraModel& view : views) {
    const int w = view.width(), h = view.height();
    const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
    std::vector<float> tile_sum(static_cast<std::size_t>(tiles_x * tiles_y), 0.0f);
    tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
      const FlushDenormals flush;
      const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
      std::array<Ray, kTile * kTile> rays;
      std::array<RayHit, kTile * kTile> ray_hits;
      std::size_t n = 0;
      for (int y = y0; y < std::min(y0 + kTile, h); ++y)
        for (int x = x0; x < std::min(x0 + kTile, w); ++x)
          rays[n++] = reflect::primaryRay(view, vec2(x + 0.5f, y + 0.5f));
      relic.intersectCoherent(std::span(rays).first(n), std::span(ray_hits).first(n));
      std::uint64_t local_hits = 0;
      float sum = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (!ray_hits[i].hit()) continue;
        ++local_hits;
        const vec3 normal = relic.shadingNormal(ray_hits[i], rays[i].direction);
        sum += ibl.specular(glm::reflect(rays[i].direction, normal), 0.2f).g;
      }
      tile_sum[static_cast<std::size_t>(tile)] = sum;
      hit_count += local_hits;
    });
    for (float s : tile_sum) sink += s;
  }
  hits = hit_count;
  if (!std::isfinite(sink)) HOLO_LOG_WARN("packet floor frame produced a non-finite sum");
  return floor_time.ms();
}

// The `fraction` quantile by nearest rank, a value that occurred as with median(): the smallest
// value with at least that fraction of the values at or below it; 0 for no values.
double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const double rank = std::ceil(std::clamp(fraction, 0.0, 1.0) * static_cast<double>(values.size()));
  const std::size_t k = std::min(values.size(), static_cast<std::size_t>(std::max(1.0, rank))) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// CPU time of the whole process (every thread), seconds.
double processCpuSeconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The CPU time of the process so far, to the nanosecond (getrusage counts in scheduler ticks), ms.
double processCpuMs() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

// The CPU time of the calling thread so far, ms.
double threadCpuMs() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

// Minor page faults of the process so far: memory freshly mapped and zeroed by the kernel (large
// buffers allocated per frame instead of reused).
long pageFaults() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Mean absolute difference in 8-bit sRGB code values over the four faces' displayed images.
double meanAbsCodes(const reflect::FrameResult& a, const reflect::FrameResult& b) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t v = 0; v < a.views.size() && v < b.views.size(); ++v) {
    sum += cv::norm(a.views[v].display, b.views[v].display, cv::NORM_L1);
    n += a.views[v].display.total() * 3;
  }
  return n > 0 ? sum / double(n) : 0.0;
}

// Keeps the first `n` cameras of `installation` (0 or more than it has: all).
void keepCameras(Installation& installation, int n) {
  if (n <= 0 || static_cast<std::size_t>(n) >= installation.cameras.size()) return;
  const auto keep = [n](auto& per_camera) {
    if (per_camera.size() > static_cast<std::size_t>(n)) per_camera.resize(static_cast<std::size_t>(n));
  };
  keep(installation.sources);
  keep(installation.cameras);
  keep(installation.capture_options);
  keep(installation.background);
  keep(installation.colour_gains);
  keep(installation.depth_correction);
  keep(installation.depth_to_colour);
}

// The scene's installation; live, its cameras replay frames simulated now (ReplayedSource).
Installation installation(const FrameBenchOptions& options) {
  FrameLoopOptions recorded = options.loop;
  recorded.live = false;  // live: simulated as fast as they can be, then paced by the replay
  Installation installation = simulated::installationFor(options.loop.live ? recorded : options.loop);
  keepCameras(installation, options.cameras);
  if (!options.loop.live) return installation;
  ProgressReporter progress(static_cast<std::int64_t>(installation.sources.size()), "recording the cameras");
  for (auto& source : installation.sources) {
    source =
        std::make_unique<ReplayedSource>(std::move(source), options.live_recorded_frames, installation.fps);
    progress.update(1);
  }
  progress.done();
  installation.simulated_cameras = false;  // what they deliver was simulated before the run
  return installation;
}

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;

// 64-bit FNV-1a of the four faces' displayed pixels, row by row, continuing from `hash`.
std::uint64_t foldDisplays(const reflect::FrameResult& frame, std::uint64_t hash) {
  for (const reflect::ViewImages& view : frame.views)
    for (int y = 0; y < view.display.rows; ++y) {
      const std::uint8_t* row = view.display.ptr<std::uint8_t>(y);
      for (std::size_t i = 0; i < std::size_t(view.display.cols) * view.display.elemSize(); ++i) {
        hash ^= row[i];
        hash *= 1099511628211ull;
      }
    }
  return hash;
}

}  // namespace

FrameBenchRun::FrameBenchRun(FrameBenchOptions options) : options_(std::move(options)) {
  const Stopwatch setup;
  if (options_.preload && !options_.loop.live)
    options_.loop.preload_frames = options_.warmup + options_.frames + 1;  // + the last prefetch
  loop_ = std::make_unique<FrameLoop>(options_.loop, installation(options_), nullptr);
  result_.setup_s = setup.seconds();
  progress_ = std::make_unique<ProgressReporter>(options_.warmup + options_.frames, "bench frame");
  for (int i = 0; i < options_.warmup; ++i) {
    loop_->step();
    progress_->update(1);
  }
  reference_settings_ = options_.loop.tracer;
  setAntiAliasing(reference_settings_, reflect::AntiAliasing::Full);
  reference_settings_.static_reuse_distance = 0.0f;
  reference_settings_.relic_interreflection = true;
  digest_ = kFnvOffset;
  cpu_start_s_ = processCpuSeconds();
  faults_start_ = pageFaults();
  wall_.restart();
  cpu_after_last_ = processCpuMs();
}

FrameBenchRun::~FrameBenchRun() = default;

void FrameBenchRun::measureFrame() {
  // Overlapped, live or simulating its cameras during the run, the frame's work (the worker's
  // foreground, the capture threads) went on since the last frame's end; else nothing of it runs
  // before step(), and another run's frames may have run since.
  const bool works_between_frames = options_.loop.overlap || options_.loop.live || !options_.preload;
  const double cpu_before = works_between_frames ? cpu_after_last_ : processCpuMs();
  const double thread_cpu_before = threadCpuMs();
  result_.reports.push_back(loop_->step());
  result_.loop_thread_cpu_ms.push_back(threadCpuMs() - thread_cpu_before);
  cpu_after_last_ = processCpuMs();
  result_.frame_cpu_ms.push_back(cpu_after_last_ - cpu_before);
  views_.push_back(loop_->faceViews());
  if (options_.reference)  // untimed, but it perturbs the overlapped worker's times
    error_codes_.push_back(meanAbsCodes(loop_->lastResult(), loop_->renderReference(reference_settings_)));
  if (options_.digest) digest_ = foldDisplays(loop_->lastResult(), digest_);
  progress_->update(1);
}

FrameBenchmark FrameBenchRun::finish() {
  FrameBenchmark result = std::move(result_);
  const FrameBenchOptions& options = options_;
  FrameLoop& loop = *loop_;
  const std::vector<FrameReport>& reports = result.reports;
  // The frames ran back to back, as in the product: the worker computing the next frame's
  // foreground must not compete with a floor measurement (nor get free time during one). The
  // floor of each frame's views is measured after the frames, with the worker idle.
  loop.waitForWorker();
  // How many cores the frames kept busy on average (both: the stages left none idle).
  result.busy_cores = (processCpuSeconds() - cpu_start_s_) / std::max(1e-9, wall_.seconds());
  result.page_faults_per_frame = double(pageFaults() - faults_start_) / std::max(1, options.frames);
  std::vector<double> floor_ms, floor_cpu_ms, single_ray_floor_ms;
  for (const std::vector<CameraModel>& frame_views : views_) {
    const double floor_cpu_before = processCpuMs();
    floor_ms.push_back(packetFloorMs(loop, frame_views, loop.ibl(), result.floor_relic_pixels));
    floor_cpu_ms.push_back(processCpuMs() - floor_cpu_before);
    single_ray_floor_ms.push_back(singleRayFloorMs(loop, frame_views, loop.ibl()));
  }
  progress_->done();
  result.median = medianTimes(reports);
  result.passes = medianPasses(reports);
  result.cameras = loop.cameraFrameCounts();
  result.floor_ms = median(floor_ms);
  result.floor_cpu_ms = median(floor_cpu_ms);
  result.single_ray_floor_ms = median(single_ray_floor_ms);
  if (options.reference && !error_codes_.empty()) {
    result.error_vs_reference_codes = median(error_codes_);
    result.error_vs_reference_max_codes = *std::max_element(error_codes_.begin(), error_codes_.end());
  }
  if (options.digest) result.display_digest = digest_;
  std::vector<double> frame_ms, latency_ms;
  std::array<std::vector<double>, 5> parts_ms;
  for (const FrameReport& report : reports) {
    frame_ms.push_back(report.times.total);
    if (const double ms = report.arrivalToPresentMs(); ms >= 0) {
      latency_ms.push_back(ms);
      const LatencyParts parts = report.latencyParts();
      const std::array<double, 5> values{parts.in_mailbox, parts.foreground, parts.waiting_for_loop,
                                         parts.rendering, parts.presenting};
      for (std::size_t k = 0; k < values.size(); ++k) parts_ms[k].push_back(values[k]);
    }
  }
  result.frame_p99_ms = percentile(frame_ms, 0.99);
  result.frame_cpu_median_ms = median(result.frame_cpu_ms);
  result.frame_cpu_p99_ms = percentile(result.frame_cpu_ms, 0.99);
  if (options.loop.live && !latency_ms.empty()) {
    result.latency_median_ms = median(latency_ms);
    result.latency_p99_ms = percentile(latency_ms, 0.99);
    result.latency_parts_median_ms =
        LatencyParts{median(parts_ms[0]), median(parts_ms[1]), median(parts_ms[2]), median(parts_ms[3]),
                     median(parts_ms[4])};
  }
  return result;
}

FrameBenchmark benchFrame(FrameBenchOptions options) {
  FrameBenchRun run(std::move(options));
  for (int i = 0; i < run.frames(); ++i) run.measureFrame();
  return run.finish();
}

}  // namespace holo::eval
