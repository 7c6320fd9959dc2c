// `holopyramid kiosk [--config FILE] [--headless]`: the appliance mode run by systemd
// (packaging/holopyramid.service, docs/kiosk.md). The kiosk module does the supervision; this
// file wires it to a frame source.
//
// Frame source: until the live frame loop (`holopyramid run`) lands, the kiosk presents the
// display module's alignment test pattern through the real presenters (EGL headless or GLFW
// windows), at a view resolution that follows the degradation level. Plugging in the frame
// loop is one line: makeFrameSource() returns its RenderFrame callback instead.
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/imgproc.hpp>

#include "command.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"
#include "holo/display/presenter.hpp"
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
  std::shared_ptr<display::Presenter> presenter_;  // shared: RenderFrame is copyable
  bool headless_;
  std::shared_ptr<kiosk::FaultInjector> faults_;
  display::FaceImages patterns_;
  int pattern_side_ = 0;
};

std::string displaySection(const ConfigNode& root) {
  return root.has("display") ? YAML::Dump(root.yaml()["display"]) : std::string();
}

kiosk::RenderFrame makeFrameSource(const kiosk::LoadedConfig& config, bool headless) {
  return TestPatternSource(displayConfigOf(config.root), headless);
}

struct KioskOptions {
  std::string config = "/etc/holopyramid/holopyramid.yaml";
  std::string state_dir = "/var/lib/holopyramid";
  bool headless = false;
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
  std::shared_ptr<kiosk::RenderFrame> source =
      std::make_shared<kiosk::RenderFrame>(makeFrameSource(loaded, options.headless));
  kiosk::KioskLoop loop(
      loaded, [source](const kiosk::FrameRequest& r) { return (*source)(r); },
      [&] {
        kiosk::LoadedConfig reloaded = load();
        // Changed display settings need a fresh presenter. The old one goes first: two EGL
        // presenters alive at once in one process disturb each other's context.
        if (displaySection(reloaded.root) != displaySection(loaded.root)) {
          HOLO_LOG_INFO("display settings changed: restarting the presenter");
          *source = {};
          *source = makeFrameSource(reloaded, options.headless);
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
