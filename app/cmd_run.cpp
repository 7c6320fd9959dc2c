// `holopyramid run`: the product's main job. The live pipeline on the cameras, relic and panorama
// of a configuration file (--config with capture: and exhibit: sections, installation.hpp) or on a
// scene of the simulated museum, on the monitors (GLFW) or headless (EGL) into PNG frames, an MP4
// and a timing table. With --ar-camera N, the live AR check view of camera N instead
// (pipeline/ar_check_view.hpp): in a window, or headless into ar_cameraN.mp4, PNG frames and its
// frame rate.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "command.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/progress.hpp"
#include "holo/display/display_config.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/eval/frame_timing_report.hpp"
#include "holo/pipeline/ar_check_view.hpp"
#include "holo/pipeline/calibrated_display.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::app {

using namespace holo::pipeline;
namespace {

struct RunOptions {
  FrameLoopOptions loop;
  std::string aa = "edges";  // --aa
  std::string config_file;
  std::string layout;
  bool headless = false;
  bool relearn_background = false;
  int frames = 0;
  std::string out = "out/run";
  std::string json;
  int png_every = 10;
  int ar_camera = -1;
  int ar_spp = 1;
  int ar_max_samples = 1024;
  RunOptions() { loop.view_size = kViewSizeFromScreen; }
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

// The live AR check view of camera options.ar_camera: a window (the composite on the first
// output, not mirrored) or headless ar_cameraN.mp4 and PNGs; per frame the time to grab the
// camera's frame and the time to composite it, their medians and the composite's frame rate.
int runArCamera(RunOptions options) {
  if (!options.config_file.empty()) options.loop.config = options.config_file;
  if (!options.headless) options.loop.live = true;  // a window shows the cameras as they deliver
  Installation installation = simulated::installationFor(options.loop);
  ar::LiveCompositeSettings settings;
  settings.view.composite.spp = options.ar_spp;
  settings.max_samples = options.ar_max_samples;
  ArLiveView view(installation, options.ar_camera, settings);
  const CameraModel& camera = view.camera();
  const cv::Size size(camera.width(), camera.height());
  const std::filesystem::path out(options.out);
  const std::string stem = "ar_camera" + std::to_string(options.ar_camera);
  std::unique_ptr<display::VideoFileWriter> video;
  std::unique_ptr<display::QuadViewPresenter> window;
  if (options.headless) {
    std::filesystem::create_directories(out);
    video = std::make_unique<display::VideoFileWriter>(out / (stem + ".mp4"), size, installation.fps);
  } else {
    display::DisplayConfig config;
    config.layout = display::LayoutKind::Monitors;
    config.fullscreen = false;
    config.output_size = size;
    config.faces[0].mirror = false;
    window = display::makeWindowPresenter(config);
  }
  const int frames = options.frames > 0 ? options.frames : (options.headless ? 30 : 0);
  std::vector<double> grab_ms, composite_ms, composite_cpu_ms, reset_cpu_ms;
  int resets = 0, last_samples = 0, relic_pixels = 0, traced_pixels = 0;
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  for (int n = 0; frames == 0 || n < frames; ++n) {
    const auto t0 = Clock::now();
    std::optional<ar::LiveCompositeFrame> frame = view.step();
    if (!frame) break;
    const double total = ms(Clock::now() - t0);
    composite_ms.push_back(frame->ms);
    composite_cpu_ms.push_back(frame->cpu_ms);
    if (frame->reset) reset_cpu_ms.push_back(frame->cpu_ms);
    grab_ms.push_back(total - frame->ms);
    resets += frame->reset ? 1 : 0;
    last_samples = frame->samples;
    relic_pixels = frame->relic_pixels;
    traced_pixels = frame->traced_pixels;
    if (video) {
      video->write(frame->image);
      if (options.png_every > 0 && n % options.png_every == 0)
        display::writePngAtomically(out / fmt::format("{}_{:05d}.png", stem, n), frame->image);
    } else {
      window->present({frame->image, cv::Mat(), cv::Mat(), cv::Mat()});
      if (!window->isOpen()) break;
    }
  }
  if (video) video->finish();
  if (window) window->finish();
  const double composite = median(composite_ms);
  const std::string report = fmt::format(
      "ar camera: {}\ninstallation: {}\nsize: {}x{}\nframes: {}\nsamples per frame: {}\n"
      "accumulations started: {}\nsamples at the end: {}\nrelic pixels: {}{}\ntraced pixels: {}\n"
      "composite ms (median): {:.1f}\ncomposite fps: {:.1f}\n"
      "composite CPU ms (median, all threads): {:.1f}\n"
      "first frame of an accumulation CPU ms (median): {:.1f}\ngrab ms (median, {}): {:.1f}\n",
      options.ar_camera, installation.name, size.width, size.height, composite_ms.size(), options.ar_spp,
      resets, last_samples, relic_pixels,
      relic_pixels == 0 ? " (the relic is outside this camera's view)" : "", traced_pixels, composite,
      composite > 0.0 ? 1000.0 / composite : 0.0, median(composite_cpu_ms), median(reset_cpu_ms),
      installation.simulated_cameras ? "rendering the simulated camera" : "the camera's delivery",
      median(grab_ms));
  std::cout << report;
  if (options.headless) {
    writeFileAtomically(out / (stem + ".txt"), report);
    std::cout << fmt::format("wrote {} ({}.mp4, {}_*.png, {}.txt)\n", out.string(), stem, stem, stem);
  }
  return 0;
}

int runPipeline(RunOptions options) {
  if (options.ar_camera != -1) return runArCamera(std::move(options));
  setAntiAliasing(options.loop.tracer, reflect::parseAntiAliasing(options.aa, "--aa"));
  std::optional<ConfigNode> config;
  if (!options.config_file.empty()) config = ConfigNode::loadFile(options.config_file);
  std::optional<display::LayoutKind> layout;
  if (!options.layout.empty()) layout = display::parseLayoutKind(options.layout, "--layout");
  display::DisplayConfig display_config =
      config ? calibratedDisplayConfig(*config, layout) : display::DisplayConfig{};
  if (layout) display_config.layout = *layout;
  // A configuration that names cameras runs on them; one with only a display: section lays out
  // the simulated scene.
  if (config && describesCameras(*config)) options.loop.config = options.config_file;
  if (!options.loop.relic.empty() && !options.loop.config.empty())
    throw InputError("--relic", "relic",
                     "no --relic with a configuration naming cameras (" + options.config_file +
                         " shows the relic of its exhibit: section)",
                     options.loop.relic);
  const int frames = options.frames > 0 ? options.frames : (options.headless ? 30 : 0);
  // Headless runs are deterministic unless --live: the same scene always gives the same frames,
  // whatever the machine's speed.
  if (!options.headless) options.loop.live = true;

  // The installation first: the recording's frame rate is the cameras'.
  Installation installation =
      options.loop.config.empty()
          ? simulated::museumInstallation(options.loop.scene, options.loop.live, options.loop.panorama_width,
                                          options.loop.relic)
          : loadInstallation(*config, {.relearn_background = options.relearn_background,
                                       .simulated_sources = simulated::configuredSources()});
  // A configuration without cameras may still tune the simulated museum's depth filter.
  if (options.loop.config.empty() && config) readDepthFilterSection(*config, installation);
  std::unique_ptr<display::QuadViewPresenter> presenter;
  const std::filesystem::path out(options.out);
  if (options.headless) {
    display::RecordingSettings recording;
    recording.out_dir = out;
    recording.fps = installation.fps;
    recording.png_every = options.png_every;
    presenter = display::makeRecordingPresenter(display::makeHeadlessPresenter(display_config), recording);
  } else {
    presenter = display::makeWindowPresenter(display_config);
  }

  FrameLoop loop(options.loop, std::move(installation), std::move(presenter));
  std::vector<FrameReport> reports;
  ProgressReporter progress(frames > 0 ? frames : 0, "frames");
  while (frames == 0 || static_cast<int>(reports.size()) < frames) {
    FrameReport report = loop.step();
    if (report.cameras_ended) {
      HOLO_LOG_INFO("every camera's stream ended after {} frames", reports.size());
      break;
    }
    reports.push_back(std::move(report));
    progress.update(1);
    if (!reports.back().presented && !options.headless) break;  // the window was closed
  }
  progress.done();
  loop.finish();

  const StageTimes median = eval::medianTimes(reports);
  const CameraFrameCounts cameras = loop.cameraFrameCounts();
  const std::string table = eval::formatTimingTable(median, reports, cameras);
  std::cout << table;
  if (options.headless) {
    writeFileAtomically(out / "timing.txt", table);
    writeFileAtomically(out / "timing.json", eval::timingJson(median, reports, cameras));
    std::cout << fmt::format("wrote {} (quadview.mp4, frame_*.png, timing.txt, timing.json)\n", out.string());
  }
  if (!options.json.empty()) writeFileAtomically(options.json, eval::timingJson(median, reports, cameras));
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "run",
    [](CLI::App& sub) {
      auto options = std::make_shared<RunOptions>();
      sub.add_option("--scene", options->loop.scene, "Built-in scene (see `holopyramid scenes`) or YAML file")
          ->capture_default_str();
      sub.add_option("--relic", options->loop.relic,
                     "Built-in relic or glTF file in place of the scene's (fitted on the pedestal unless the "
                     "scene says fit_relic: false)");
      sub.add_option("--config", options->config_file,
                     "YAML configuration: display: section; with capture: and exhibit: sections, runs on "
                     "those cameras, calibration, relic and panorama instead of --scene");
      sub.add_option("--layout", options->layout, "monitors | cross (overrides the configuration)");
      sub.add_flag("--headless", options->headless, "Render offscreen through EGL into --out, no windows");
      sub.add_flag("--relearn-background", options->relearn_background,
                   "Learn the background from the first frames even when the calibration captured one");
      sub.add_flag("--live", options->loop.live,
                   "Headless too: capture threads at the cameras' rate (not deterministic)");
      sub.add_option("--frames", options->frames, "Frames to run (0: until the window closes; headless: 30)");
      sub.add_option("--out", options->out, "Headless output folder")->capture_default_str();
      sub.add_option("--png-every", options->png_every, "Headless: write every Nth frame as PNG (0: none)")
          ->capture_default_str();
      sub.add_option("--view-size", options->loop.view_size,
                     "Pixels per face view (square); 0: the size the screen shows a face at (a Full HD "
                     "cross: 360)")
          ->capture_default_str();
      sub.add_option("--aa", options->aa, "Anti-aliasing: none | edges (4 sub-samples at silhouettes) | full")
          ->capture_default_str();
      addStaticReuseOptions(sub, options->loop.tracer);
      sub.add_flag("!--no-foreground", options->loop.tracer.foreground_enabled,
                   "Static IBL reflections only (the foreground effect off)");
      sub.add_flag("!--no-eye-tracking", options->loop.track_eyes, "Default standing eyes for every face");
      addPanoramaAtInfinityFlag(sub, options->loop.panorama_at_infinity);
      addCameraTimingOptions(sub, options->loop);
      sub.add_option("--ar-camera", options->ar_camera,
                     "The live AR check view of camera N (the rig's, then the check cameras; the simulated "
                     "museum's check camera is 4) instead of the pyramid: the relic composited over its "
                     "image by delta path tracing, refined while still (headless: --out/ar_cameraN.mp4)");
      sub.add_option("--ar-spp", options->ar_spp, "--ar-camera: samples per pixel each frame adds")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 16));
      sub.add_option("--ar-max-samples", options->ar_max_samples,
                     "--ar-camera: samples per pixel a still view accumulates before it stops tracing")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--json", options->json, "Also write the timing report (medians, per frame) here");
      return [options] { return runPipeline(*options); };
    },
    "The live pipeline: cameras -> foreground -> reflections -> quad view (monitors or headless)"});

}  // namespace holo::app
