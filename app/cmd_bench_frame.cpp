// `holopyramid bench frame`: whole frames of the live pipeline on a simulated scene and the
// one-ray-per-pixel floor of the same run (eval/frame_benchmark.hpp); prints the medians and how
// far above the floor the frame is.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "command.hpp"
#include "holo/core/files.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/eval/frame_benchmark.hpp"
#include "holo/eval/frame_timing_report.hpp"

namespace holo::app {

using namespace holo::eval;
using namespace holo::pipeline;
namespace {

struct BenchFrameCommand {
  FrameBenchOptions bench;
  std::string aa = "edges";  // --aa
  std::string json;
};

int runBenchFrame(BenchFrameCommand command) {
  setAntiAliasing(command.bench.loop.tracer, reflect::parseAntiAliasing(command.aa, "--aa"));
  const FrameBenchmark b = benchFrame(command.bench);
  const FrameBenchOptions& options = command.bench;
  std::cout << formatTimingTable(b.median, b.reports, b.cameras);
  std::cout << "tracer passes, median ms (all views):";
  for (const auto& [name, ms] : b.passes) std::cout << fmt::format(" {} {:.2f}", name, ms);
  std::cout << "\n";
  if (b.error_vs_reference_codes)
    std::cout << fmt::format(
        "error against the same frames traced fresh with 4 samples per pixel: median {:.3f}, largest {:.3f} "
        "sRGB codes (mean absolute, 8-bit, four faces)\n",
        *b.error_vs_reference_codes, *b.error_vs_reference_max_codes);
  {
    std::uint64_t shaded = 0, bounced = 0, rays = 0;
    for (const FrameReport& r : b.reports) {
      shaded += r.shaded_samples;
      bounced += r.interreflected_samples;
      rays += r.interreflection_rays;
    }
    std::cout << fmt::format(
        "interreflection: {} of the {} relic samples shaded afresh in the measured frames ({:.1f}%) cast {} "
        "rays against the relic ({})\n",
        bounced, shaded, shaded > 0 ? 100.0 * double(bounced) / double(shaded) : 0.0, rays,
        b.reports.empty() ? std::string("no frames") : b.reports.back().plan);
  }
  if (b.display_digest)
    std::cout << fmt::format("displayed faces of the measured frames: FNV-1a digest {:016x}\n",
                             *b.display_digest);
  if (b.latency_median_ms && b.latency_p99_ms)
    std::cout << fmt::format(
        "live: cameras replayed at their rate on their capture threads; arrival-to-present latency of the "
        "oldest camera frame shown: median {:.1f} ms, p99 {:.1f} ms (bars 50 and 80 ms: {}, {})\n",
        *b.latency_median_ms, *b.latency_p99_ms, *b.latency_median_ms <= 50.0 ? "met" : "not met",
        *b.latency_p99_ms <= 80.0 ? "met" : "not met");
  if (b.latency_median_ms && b.latency_parts_median_ms && b.median.total > 0) {
    const LatencyParts& p = *b.latency_parts_median_ms;
    std::cout << fmt::format(
        "latency: median {:.2f} frame times; its parts (medians, ms): in the mailbox {:.1f}, foreground "
        "{:.1f}, waiting for the loop {:.1f}, rendering {:.1f}, presenting {:.1f}\n",
        *b.latency_median_ms / b.median.total, p.in_mailbox, p.foreground, p.waiting_for_loop, p.rendering,
        p.presenting);
  }
  std::cout << fmt::format(
      "frame time: median {:.1f} ms, p99 {:.1f} ms = {:.2f}x the median (bar 1.5x: {})\n", b.median.total,
      b.frame_p99_ms, b.median.total > 0 ? b.frame_p99_ms / b.median.total : 0.0,
      b.frame_p99_ms <= 1.5 * b.median.total ? "met" : "not met");
  std::cout << fmt::format(
      "CPU per frame (all threads): median {:.1f} ms, p99 {:.1f} ms = {:.2f}x the median\n",
      b.frame_cpu_median_ms, b.frame_cpu_p99_ms,
      b.frame_cpu_median_ms > 0 ? b.frame_cpu_p99_ms / b.frame_cpu_median_ms : 0.0);
  if (options.preload && !options.loop.live)
    std::cout << fmt::format(
        "camera frames simulated before timing and replayed (setup incl. simulation {:.1f} s); "
        "--no-preload simulates them during the run\n",
        b.setup_s);
  std::cout << fmt::format(
      "floor (1 primary ray + 1 IBL lookup per pixel, 4 views of {}x{}, {} relic pixels): {:.2f} ms "
      "in coherent packets of {} over 8x8 tiles; {:.2f} ms one ray at a time\n"
      "frame / floor: {:.1f}x (against the one-ray floor: {:.1f}x)\n"
      "CPU per frame / CPU of the packet floor ({:.2f} ms): {:.2f}x\n"
      "cores busy during the frames: {:.2f} of {} ({}); {:.0f} page faults per frame\n",
      options.loop.view_size, options.loop.view_size, b.floor_relic_pixels, b.floor_ms,
      RayScene::nativePacketWidth(), b.single_ray_floor_ms, b.frameOverFloor(),
      b.single_ray_floor_ms > 0 ? b.median.total / b.single_ray_floor_ms : 0.0, b.floor_cpu_ms,
      b.frameCpuOverFloorCpu(), b.busy_cores, std::thread::hardware_concurrency(),
      options.loop.overlap ? "next frame's foreground overlapped" : "no overlap", b.page_faults_per_frame);
  if (!command.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(timingJson(b.median, b.reports, b.cameras));
    j["floor_ms"] = b.floor_ms;
    j["floor_packet_width"] = RayScene::nativePacketWidth();
    j["frame_over_floor"] = b.frameOverFloor();
    j["floor_cpu_ms"] = b.floor_cpu_ms;
    j["frame_cpu_over_floor_cpu"] = b.frameCpuOverFloorCpu();
    j["single_ray_floor_ms"] = b.single_ray_floor_ms;
    j["view_size"] = options.loop.view_size;
    j["scene"] = options.loop.scene;
    j["relic"] = options.loop.relic;
    j["cameras_preloaded"] = options.preload;
    j["overlap"] = options.loop.overlap;
    j["fresh_frame_wait_ms"] = options.loop.fresh_frame_wait_ms;
    j["busy_cores"] = b.busy_cores;
    j["live"] = options.loop.live;
    j["frame_p99_ms"] = b.frame_p99_ms;
    j["frame_cpu_median_ms"] = b.frame_cpu_median_ms;
    j["frame_cpu_p99_ms"] = b.frame_cpu_p99_ms;
    j["frame_cpu_ms"] = b.frame_cpu_ms;
    if (b.latency_median_ms) j["latency_median_ms"] = *b.latency_median_ms;
    if (b.latency_p99_ms) j["latency_p99_ms"] = *b.latency_p99_ms;
    if (b.latency_median_ms && b.median.total > 0)
      j["latency_median_frames"] = *b.latency_median_ms / b.median.total;
    if (const auto& p = b.latency_parts_median_ms)
      j["latency_parts_median_ms"] = {{"in_mailbox", p->in_mailbox},
                                      {"foreground", p->foreground},
                                      {"waiting_for_loop", p->waiting_for_loop},
                                      {"rendering", p->rendering},
                                      {"presenting", p->presenting}};
    j["page_faults_per_frame"] = b.page_faults_per_frame;
    if (b.error_vs_reference_codes) {
      j["error_vs_full_aa_codes"] = *b.error_vs_reference_codes;
      j["error_vs_full_aa_max_codes"] = *b.error_vs_reference_max_codes;
    }
    if (b.display_digest) j["display_digest"] = fmt::format("{:016x}", *b.display_digest);
    for (const auto& [name, ms] : b.passes) j["passes_ms"][name] = ms;
    j["anti_aliasing"] = command.aa;
    j["static_reuse_m"] = options.loop.tracer.static_reuse_distance;
    writeFileAtomically(command.json, j.dump(2));
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "bench frame",
    [](CLI::App& sub) {
      auto command = std::make_shared<BenchFrameCommand>();
      FrameBenchOptions* options = &command->bench;
      sub.add_option("--scene", options->loop.scene, "Built-in scene or YAML file")->capture_default_str();
      sub.add_option("--relic", options->loop.relic,
                     "Built-in relic or glTF file in place of the scene's (e.g. glass-vase)");
      sub.add_option("--refraction-depth", options->loop.tracer.refraction_depth,
                     "Interface events a transmitted path follows (0: measured on the relic)")
          ->capture_default_str();
      sub.add_option("--refraction-stride", options->loop.tracer.refraction_stride,
                     "Pixels between the traced transmitted paths; the samples between blend them (1: every "
                     "sample traces)")
          ->capture_default_str()
          ->check(CLI::Range(1, 4));
      sub.add_option("--refraction-branch-rays", options->loop.tracer.refraction_branch_rays,
                     "Rays a transmitted path may spend following the light reflected inside at an exit (0: "
                     "summed as between parallel walls)")
          ->capture_default_str()
          ->check(CLI::Range(0, 64));
      sub.add_option("--refraction-branch-weight", options->loop.tracer.refraction_branch_weight,
                     "Share of the entering light below which that light is summed, not followed")
          ->capture_default_str()
          ->check(CLI::Range(0.0f, 1.0f));
      sub.add_option(
             "--refraction-supersample", options->loop.tracer.refraction_supersample_contrast,
             "Luminance ratio of the transmitted light within a pixel above which its samples take the "
             "mean of more paths (0: off)")
          ->capture_default_str();
      sub.add_option("--view-size", options->loop.view_size, "Pixels per face view")->capture_default_str();
      sub.add_option("--frames", options->frames, "Measured frames")->capture_default_str();
      sub.add_option("--warmup", options->warmup, "Frames run before measuring")->capture_default_str();
      sub.add_option("--aa", command->aa, "Anti-aliasing: none | edges (4 sub-samples at silhouettes) | full")
          ->capture_default_str();
      addStaticReuseOptions(sub, options->loop.tracer);
      sub.add_flag("!--no-interreflection", options->loop.tracer.relic_interreflection,
                   "No bounce where the relic reflects itself (on by default where the relic can see "
                   "itself; a convex relic casts no ray)");
      sub.add_flag("--digest", options->digest,
                   "Print an FNV-1a digest of every measured frame's displayed faces (untimed)");
      sub.add_flag("!--no-foreground", options->loop.tracer.foreground_enabled, "IBL only");
      sub.add_flag_callback(
          "--no-light-effects",
          [options] {
            reflect::TracerSettings& t = options->loop.tracer;
            t.evaluation.self_occlusion = false;
            t.evaluation.visitor_light = false;
            t.evaluation.axis_aligned_filter = false;
            t.rough_interreflection_roughness = 2.0f;
            t.refinement_sets = 1;
          },
          "Without the relic's self-occlusion, rough interreflection lobe, visitors' light, axis-aligned "
          "filter and progressive refinement (the frame they are measured against)");
      addPanoramaAtInfinityFlag(sub, options->loop.panorama_at_infinity);
      sub.add_flag(
          "--reference", options->reference,
          "Also render every measured frame with 4 samples per pixel, the interreflection bounce and no "
          "reuse (untimed) and report the displayed images' difference");
      sub.add_flag("!--no-preload", options->preload,
                   "Simulate the cameras during the run (competes with the frame for the cores) instead of "
                   "before it");
      sub.add_flag("--live", options->loop.live,
                   "Cameras at their rate on their own capture threads (a loop of frames simulated before "
                   "the run): drops frames the loop is late for and measures arrival-to-present latency");
      addCameraTimingOptions(sub, options->loop);
      sub.add_option("--json", command->json, "Write medians, per-frame times and the floor here");
      return [command] { return runBenchFrame(*command); };
    },
    "Median whole-frame times per stage and the one-ray-per-pixel floor (packets), from one run"});

}  // namespace holo::app
