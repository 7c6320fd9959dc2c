// `holopyramid kiosk [--config FILE] [--headless]`: the appliance mode run by systemd
// (packaging/holopyramid.service, docs/kiosk.md). The kiosk module does the supervision; this
// file wires it to a frame source.
//
// Frame sources: `pipeline` (the default) is the live frame loop of `holopyramid run`, at the
// view size and camera mode the degradation policy asks for; `test-pattern` presents the display
// module's alignment pattern through the same presenters, for checking the supervision itself
// (the process tests) without the cost of rendering.
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/imgproc.hpp>

#include "command.hpp"
#include "frame_loop.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"
#include "holo/kiosk/fault_injector.hpp"
#include "holo/kiosk/kiosk_loop.hpp"

namespace holo::app {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

display::DisplayConfig displayConfigOf(const ConfigNode& root) {
  const auto section = root.find("display");
  return section ? display::parseDisplayConfig(*section) : display::DisplayConfig{};
}

// The stand-in frame source: the four faces' test pattern, presented for real. Every 30th
// frame (headless) the presented picture is read back and checked for black, the fault the
// kiosk exists to prevent.
class TestPatternSource {
 public:
  TestPatternSource(const display::DisplayConfig& config, bool headless)
      : presenter_(headless ? display::makeHeadlessPresenter(config) : display::makeWindowPresenter(config)),
        headless_(headless),
        faults_(std::make_shared<kiosk::FaultInjector>(kiosk::FaultInjector::fromEnvironment())) {}

  kiosk::FrameReport operator()(const kiosk::FrameRequest& request) {
    kiosk::FrameReport report;
    auto t0 = Clock::now();
    const kiosk::InjectedFaults faults = faults_->beginFrame(request.index, request.quality, request.blank);
    display::FaceImages faces;  // empty images present black
    if (!request.blank && !faults.black) {
      // Lower quality levels halve the view resolution, as the real renderer will.
      const int side = std::max(40, 320 >> request.quality);
      if (pattern_side_ != side) {
        for (int f = 0; f < display::kFaceCount; ++f)
          patterns_[static_cast<std::size_t>(f)] = display::testPatternFace(f, {side, side});
        pattern_side_ = side;
      }
      faces = patterns_;
    }
    report.stage_ms["render"] = msSince(t0);
    t0 = Clock::now();
    presenter_->present(faces);
    report.stage_ms["present"] = msSince(t0);
    report.presented = presenter_->isOpen();
    if (!report.presented) report.errors.push_back("display window closed");
    if (headless_ && !request.blank && request.index % 30 == 0) {
      cv::Mat grey;
      cv::cvtColor(presenter_->readBack(), grey, cv::COLOR_BGR2GRAY);
      if (cv::countNonZero(grey) == 0) report.errors.push_back("black frame presented during opening hours");
    }
    return report;
  }

 private:
  std::shared_ptr<display::QuadViewPresenter> presenter_;  // shared: RenderFrame is copyable
  bool headless_;
  std::shared_ptr<kiosk::FaultInjector> faults_;
  display::FaceImages patterns_;
  int pattern_side_ = 0;
};

std::string displaySection(const ConfigNode& root) {
  return root.has("display") ? YAML::Dump(root.yaml()["display"]) : std::string();
}

// The product: the live frame loop on the simulated museum (real cameras plug in through the
// capture configuration), at the view size and camera mode the degradation policy asks for.
class PipelineSource {
 public:
  PipelineSource(const display::DisplayConfig& config, bool headless, const std::string& scene)
      : headless_(headless) {
    FrameLoopOptions options;
    options.scene = scene;
    options.live = true;
    full_view_size_ = options.view_size;
    loop_ = std::make_shared<FrameLoop>(
        options, headless ? display::makeHeadlessPresenter(config) : display::makeWindowPresenter(config));
  }

  kiosk::FrameReport operator()(const kiosk::FrameRequest& request) {
    kiosk::FrameReport report;
    if (request.blank) {
      loop_->presenter()->present(display::FaceImages{});  // never given: black
      report.presented = loop_->presenter()->isOpen();
      return report;
    }
    // Each quality level below the best renders views 1.25x smaller (0.64x the pixels).
    const int view_size = std::max(64, static_cast<int>(full_view_size_ / std::pow(1.25, request.quality)));
    loop_->setQuality(view_size, request.mode != kiosk::RenderMode::IblOnly);
    const FrameReport frame = loop_->step();
    report.presented = frame.presented;
    report.stage_ms = {
        {"acquisition", frame.times.acquisition},     {"foreground", frame.times.foreground},
        {"dynamic_reflections", frame.times.dynamic}, {"static_reflections", frame.times.statics},
        {"composition", frame.times.composition},     {"display", frame.times.display}};
    report.foreground_share =
        frame.foreground_points > 0
            ? std::optional<double>(
                  std::min(1.0, static_cast<double>(frame.foreground_points) / (4.0 * 640 * 360)))
            : 0.0;
    const std::vector<capture::CameraHealth> health = loop_->cameraHealth();
    for (std::size_t i = 0; i < health.size(); ++i) {
      kiosk::CameraHealth camera;
      camera.name = "camera " + std::to_string(i);
      camera.alive =
          health[i].connected && health[i].last_frame_age_s >= 0 && health[i].last_frame_age_s < 1.0;
      camera.frames = health[i].frames_completed;
      camera.dropped = health[i].frames_failed + health[i].frames_incomplete + health[i].frames_timed_out;
      camera.reconnects = health[i].reconnects;
      camera.last_frame_age_s = health[i].last_frame_age_s;
      report.cameras.push_back(camera);
    }
    if (!report.presented) report.errors.push_back("display window closed");
    if (headless_ && request.index % 30 == 0) {
      cv::Mat grey;
      cv::cvtColor(loop_->presenter()->readBack(), grey, cv::COLOR_BGR2GRAY);
      if (cv::countNonZero(grey) == 0) report.errors.push_back("black frame presented during opening hours");
    }
    return report;
  }

 private:
  std::shared_ptr<FrameLoop> loop_;  // shared: RenderFrame is copyable
  bool headless_;
  int full_view_size_ = 320;
};

kiosk::RenderFrame makeFrameSource(const kiosk::LoadedConfig& config, bool headless,
                                   const std::string& source, const std::string& scene) {
  if (source == "test-pattern") return TestPatternSource(displayConfigOf(config.root), headless);
  return PipelineSource(displayConfigOf(config.root), headless, scene);
}

struct KioskOptions {
  std::string config = "/etc/holopyramid/holopyramid.yaml";
  std::string state_dir = "/var/lib/holopyramid";
  bool headless = false;
  std::string source = "pipeline";
  std::string scene = "museum";
  std::int64_t frames = 0;
  std::optional<int> health_port;
  std::optional<std::string> health_file;
};

int runKiosk(const KioskOptions& options) {
  // Before any thread starts (health server, presenters), so all threads inherit the block.
  kiosk::SignalEvents signals;
  kiosk::SystemdNotifier notifier;
  const std::filesystem::path last_good = options.state_dir.empty()
                                              ? std::filesystem::path()
                                              : std::filesystem::path(options.state_dir) / "last-good.yaml";
  const auto load = [&] {
    kiosk::LoadedConfig loaded = kiosk::loadConfigWithFallback(
        options.config, last_good, [](const ConfigNode& root) { displayConfigOf(root); });
    if (options.health_port) loaded.kiosk.health_port = *options.health_port;
    if (options.health_file) loaded.kiosk.health_file = *options.health_file;
    return loaded;
  };
  kiosk::LoadedConfig loaded = load();
  HOLO_LOG_INFO("kiosk starting with configuration from {}", loaded.source);
  std::shared_ptr<kiosk::RenderFrame> source = std::make_shared<kiosk::RenderFrame>(
      makeFrameSource(loaded, options.headless, options.source, options.scene));
  kiosk::KioskLoop loop(
      loaded, [source](const kiosk::FrameRequest& r) { return (*source)(r); },
      [&] {
        kiosk::LoadedConfig reloaded = load();
        // Changed display settings need a fresh presenter. The old one goes first: two EGL
        // presenters alive at once in one process disturb each other's context.
        if (displaySection(reloaded.root) != displaySection(loaded.root)) {
          HOLO_LOG_INFO("display settings changed: restarting the presenter");
          *source = {};
          *source = makeFrameSource(reloaded, options.headless, options.source, options.scene);
        }
        loaded = reloaded;
        return reloaded;
      });
  return loop.run(signals, notifier, options.frames);
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "kiosk",
    [](CLI::App& sub) {
      auto options = std::make_shared<KioskOptions>();
      sub.add_option("--config", options->config, "YAML configuration (kiosk: and display: sections)")
          ->capture_default_str();
      sub.add_flag("--headless", options->headless, "Render offscreen through EGL, no windows");
      sub.add_option("--source", options->source,
                     "pipeline (the product) | test-pattern (the alignment pattern, for supervision checks)")
          ->check(CLI::IsMember({"pipeline", "test-pattern"}))
          ->capture_default_str();
      sub.add_option("--scene", options->scene, "Scene of the simulated museum the pipeline shows")
          ->capture_default_str();
      sub.add_option("--state-dir", options->state_dir,
                     "Where the last good configuration is kept ('' = nowhere)")
          ->capture_default_str();
      sub.add_option("--frames", options->frames, "Stop after N frames (0 = run until SIGTERM)");
      sub.add_option_function<int>(
          "--health-port", [options](int p) { options->health_port = p; },
          "Override kiosk.health.port (0 = any free port, -1 = off)");
      sub.add_option_function<std::string>(
          "--health-file", [options](const std::string& f) { options->health_file = f; },
          "Override kiosk.health.file ('' = none)");
      return [options] { return runKiosk(*options); };
    },
    "Appliance mode under systemd: watchdog, health, opening hours, graceful degradation"});

}  // namespace holo::app
