// `holopyramid bench frame`: whole frames of the live pipeline on a simulated scene, and in the
// same run the floor DESIGN.md sets for a frame: one primary ray per pixel of the four views
// plus one prefiltered-environment lookup at the reflected direction, with nothing else. Reports
// medians and how far above the floor the frame is.
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "command.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"
#include "holo/reflect/view.hpp"

namespace holo::app {
namespace {

struct BenchFrameOptions {
  FrameLoopOptions loop;
  std::string aa = "edges";  // --aa
  int warmup = 3;
  int frames = 10;
  bool preload = true;
  bool reference = false;  // --reference: error against 4 samples everywhere, traced fresh
  std::string json;
};

// One primary ray per pixel of every view against the relic and, where it hits, one
// prefiltered-IBL lookup at the mirror direction. Returns milliseconds.
double floorFrameMs(const FrameLoop& loop, const std::vector<CameraModel>& views,
                    const reflect::PrefilteredIbl& ibl, std::uint64_t& hits) {
  const auto t0 = Clock::now();
  std::atomic<std::uint64_t> hit_count{0};
  float sink = 0;
  for (const CameraModel& view : views) {
    const int w = view.width(), h = view.height();
    std::vector<float> row_sum(static_cast<std::size_t>(h), 0.0f);
    tbb::parallel_for(0, h, [&](int y) {
      std::uint64_t local_hits = 0;
      float sum = 0;
      for (int x = 0; x < w; ++x) {
        const Ray ray = reflect::primaryRay(view, vec2(x + 0.5f, y + 0.5f));
        const RayHit hit = loop.renderScene().relicOnly().intersect(ray);
        if (!hit.hit()) continue;
        ++local_hits;
        const vec3 n = loop.renderScene().relicOnly().shadingNormal(hit, ray.direction);
        sum += ibl.specular(glm::reflect(ray.direction, n), 0.2f).g;
      }
      row_sum[static_cast<std::size_t>(y)] = sum;
      hit_count += local_hits;
    });
    for (float s : row_sum) sink += s;
  }
  hits = hit_count;
  if (!std::isfinite(sink)) HOLO_LOG_WARN("floor frame produced a non-finite sum");
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// CPU time of the whole process (every thread), seconds.
double processCpuSeconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
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

int runBenchFrame(BenchFrameOptions options) {
  setAntiAliasing(options.loop.tracer, reflect::parseAntiAliasing(options.aa, "--aa"));
  if (options.preload)
    options.loop.preload_frames = options.warmup + options.frames + 1;  // + the last prefetch
  const auto preload_start = Clock::now();
  FrameLoop loop(options.loop, nullptr);
  const double setup_s = std::chrono::duration<double>(Clock::now() - preload_start).count();
  ProgressReporter progress(options.warmup + options.frames, "bench frame");
  for (int i = 0; i < options.warmup; ++i) {
    loop.step();
    progress.update(1);
  }
  std::vector<FrameReport> reports;
  std::vector<double> floor_ms, error_codes;
  std::uint64_t hits = 0;
  reflect::TracerSettings reference_settings = options.loop.tracer;
  setAntiAliasing(reference_settings, reflect::AntiAliasing::Full);
  reference_settings.static_reuse_distance = 0.0f;
  reference_settings.relic_interreflection = true;
  // The frames run back to back, as in the product: the worker computing the next frame's
  // foreground must not compete with a floor measurement (nor get free time during one). The
  // floor of each frame's views is measured after the frames, with the worker idle.
  std::vector<std::vector<CameraModel>> views;
  const double cpu_start = processCpuSeconds();
  const long faults_start = pageFaults();
  const auto wall_start = Clock::now();
  for (int i = 0; i < options.frames; ++i) {
    reports.push_back(loop.step());
    views.push_back(loop.faceViews());
    if (options.reference)  // untimed, but it perturbs the overlapped worker's times
      error_codes.push_back(meanAbsCodes(loop.lastResult(), loop.renderReference(reference_settings)));
    progress.update(1);
  }
  loop.waitForWorker();
  // How many cores the frames kept busy on average (both: the stages left none idle).
  const double busy_cores = (processCpuSeconds() - cpu_start) /
                            std::max(1e-9, std::chrono::duration<double>(Clock::now() - wall_start).count());
  const double faults_per_frame = double(pageFaults() - faults_start) / std::max(1, options.frames);
  for (const std::vector<CameraModel>& frame_views : views)
    floor_ms.push_back(floorFrameMs(loop, frame_views, loop.ibl(), hits));
  progress.done();
  const StageTimes median = medianTimes(reports);
  // The acquisition of the next frame overlaps processing; what the loop waits for is counted.
  const double processing = median.total;
  const double floor = holo::median(floor_ms);
  std::cout << formatTimingTable(median, reports, loop.cameraFrameCounts());
  std::cout << "tracer passes, median ms (all views):";
  for (const auto& [name, ms] : medianPasses(reports)) std::cout << fmt::format(" {} {:.2f}", name, ms);
  std::cout << "\n";
  if (options.reference)
    std::cout << fmt::format(
        "error against the same frames traced fresh with 4 samples per pixel: median {:.3f} sRGB codes "
        "(mean absolute, 8-bit, four faces)\n",
        holo::median(error_codes));
  if (options.preload)
    std::cout << fmt::format(
        "camera frames simulated before timing and replayed (setup incl. simulation {:.1f} s); "
        "--no-preload simulates them during the run\n",
        setup_s);
  std::cout << fmt::format(
      "floor (1 primary ray + 1 IBL lookup per pixel, 4 views of {}x{}, {} relic pixels): {:.2f} ms\n"
      "frame / floor: {:.1f}x\n"
      "cores busy during the frames: {:.2f} of {} ({}); {:.0f} page faults per frame\n",
      options.loop.view_size, options.loop.view_size, hits, floor, floor > 0 ? processing / floor : 0.0,
      busy_cores, std::thread::hardware_concurrency(),
      options.loop.overlap ? "next frame's foreground overlapped" : "no overlap", faults_per_frame);
  if (!options.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(timingJson(median, reports, loop.cameraFrameCounts()));
    j["floor_ms"] = floor;
    j["frame_over_floor"] = floor > 0 ? processing / floor : 0.0;
    j["view_size"] = options.loop.view_size;
    j["scene"] = options.loop.scene;
    j["cameras_preloaded"] = options.preload;
    j["overlap"] = options.loop.overlap;
    j["busy_cores"] = busy_cores;
    j["page_faults_per_frame"] = faults_per_frame;
    if (options.reference) j["error_vs_full_aa_codes"] = holo::median(error_codes);
    for (const auto& [name, ms] : medianPasses(reports)) j["passes_ms"][name] = ms;
    j["anti_aliasing"] = options.aa;
    j["static_reuse_m"] = options.loop.tracer.static_reuse_distance;
    writeFileAtomically(options.json, j.dump(2));
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "bench frame",
    [](CLI::App& sub) {
      auto options = std::make_shared<BenchFrameOptions>();
      sub.add_option("--scene", options->loop.scene, "Built-in scene or YAML file")->capture_default_str();
      sub.add_option("--view-size", options->loop.view_size, "Pixels per face view")->capture_default_str();
      sub.add_option("--frames", options->frames, "Measured frames")->capture_default_str();
      sub.add_option("--warmup", options->warmup, "Frames run before measuring")->capture_default_str();
      sub.add_option("--aa", options->aa, "Anti-aliasing: none | edges (4 sub-samples at silhouettes) | full")
          ->capture_default_str();
      sub.add_option("--static-reuse", options->loop.tracer.static_reuse_distance,
                     "Metres an eye may move before a view's hit points are traced again (0: identical only)")
          ->capture_default_str();
      sub.add_flag("--interreflection", options->loop.tracer.relic_interreflection,
                   "One bounce where the relic reflects itself (off in the live loop)");
      sub.add_flag("!--no-foreground", options->loop.tracer.foreground_enabled, "IBL only");
      sub.add_flag(
          "--reference", options->reference,
          "Also render every measured frame with 4 samples per pixel, the interreflection bounce and no "
          "reuse (untimed) and report the displayed images' difference");
      sub.add_flag("!--no-preload", options->preload,
                   "Simulate the cameras during the run (competes with the frame for the cores) instead of "
                   "before it");
      sub.add_flag("!--no-overlap", options->loop.overlap,
                   "Compute each frame's foreground after the previous frame instead of during it");
      sub.add_option("--json", options->json, "Write medians, per-frame times and the floor here");
      return [options] { return runBenchFrame(*options); };
    },
    "Median whole-frame times per stage and the one-ray-per-pixel floor, from one run"});

}  // namespace holo::app
