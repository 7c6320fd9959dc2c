// `holopyramid kiosk [--config FILE] [--headless]`: the appliance mode run by systemd
// (packaging/holopyramid.service, docs/kiosk.md). The kiosk module does the supervision; this
// file wires it to a frame source of the pipeline module (kiosk_frame_source.hpp): `pipeline`
// on the configuration's cameras when it has a `capture:` section, else on the simulated museum,
// or `test-pattern`.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "command.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"
#include "holo/kiosk/fault_injector.hpp"
#include "holo/kiosk/kiosk_loop.hpp"
#include "holo/pipeline/calibrated_display.hpp"
#include "holo/pipeline/exhibit_config.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/pipeline/kiosk_frame_source.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::app {

using namespace holo::pipeline;
namespace {

std::string sectionText(const ConfigNode& root, const std::string& section) {
  return root.has(section) ? YAML::Dump(root.yaml()[section]) : std::string();
}

// The exhibit section without its playlist: what a running frame loop was built from.
std::string exhibitSettingsText(const ConfigNode& root) {
  if (!root.has("exhibit")) return {};
  YAML::Node exhibit = YAML::Clone(root.yaml()["exhibit"]);
  if (exhibit.IsMap()) exhibit.remove("relics");
  return YAML::Dump(exhibit);
}

struct KioskOptions {
  std::string config = "/etc/holopyramid/holopyramid.yaml";
  std::string state_dir = "/var/lib/holopyramid";
  bool headless = false;
  bool relearn_background = false;
  std::string source = "pipeline";
  std::string scene = "museum";
  int view_size = kViewSizeFromScreen;
  std::int64_t frames = 0;
  std::optional<int> health_port;
  std::optional<std::string> health_file;
};

// `installation`: the one the configuration describes, loaded when it was validated; none when
// it names no cameras (then the simulated museum).
kiosk::RenderFrame makeFrameSource(const kiosk::LoadedConfig& config, const KioskOptions& options,
                                   std::optional<Installation> installation,
                                   const std::shared_ptr<ExhibitControl>& control) {
  const display::DisplayConfig display_config = calibratedDisplayConfig(config.root);
  if (options.source == "test-pattern")
    return pipeline::testPatternFrameSource(display_config, options.headless);
  if (!installation) {
    installation =
        simulated::museumInstallation(options.scene, /*paced=*/true, FrameLoopOptions{}.panorama_width);
    readDepthFilterSection(config.root, *installation);
  }
  return pipeline::pipelineFrameSource(display_config, options.headless, std::move(*installation),
                                       options.view_size, {.wait_for_next_relic = false, .control = control});
}

int runKiosk(const KioskOptions& options) {
  // Before any thread starts (health server, presenters), so all threads inherit the block.
  kiosk::SignalEvents signals;
  kiosk::SystemdNotifier notifier;
  const std::filesystem::path last_good = options.state_dir.empty()
                                              ? std::filesystem::path()
                                              : std::filesystem::path(options.state_dir) / "last-good.yaml";
  // A configuration is usable when its display settings parse and, if it names cameras, its
  // installation loads (cameras, calibration, relic, panorama): a broken one falls back to the
  // last good copy instead of leaving the screen black. The installation of the configuration
  // validated last (the one loaded) is kept for the frame source, so its files are read once.
  std::optional<Installation> installation;
  const auto validate = [&installation, &options](const ConfigNode& root) {
    installation.reset();
    calibratedDisplayConfig(root);
    if (describesCameras(root)) {
      installation = loadInstallation(root, {.relearn_background = options.relearn_background,
                                             .simulated_sources = simulated::configuredSources()});
    } else if (describesPlaylist(root) && options.source == "pipeline") {
      // The playlist in the simulated museum (its own hall for entries naming no panorama).
      const ExhibitConfig exhibit = parseExhibitConfig(root["exhibit"]);
      installation =
          simulated::museumInstallation(options.scene, /*paced=*/true, FrameLoopOptions{}.panorama_width);
      loadPlaylist(root["exhibit"], exhibit, *installation);
      readDepthFilterSection(root, *installation);
    } else {
      // The simulated museum's depth filter settings are checked here, so a bad one falls back.
      Installation settings;
      readDepthFilterSection(root, settings);
    }
  };
  const auto load = [&] {
    kiosk::LoadedConfig loaded = kiosk::loadConfigWithFallback(options.config, last_good, validate);
    if (options.health_port) loaded.kiosk.health_port = *options.health_port;
    if (options.health_file) loaded.kiosk.health_file = *options.health_file;
    return loaded;
  };
  kiosk::LoadedConfig loaded = load();
  HOLO_LOG_INFO("kiosk starting with configuration from {}", loaded.source);
  // A reload that changes only the playlist hands it to the running source (ExhibitControl): the
  // frame loop and its picture stay.
  const auto control = std::make_shared<ExhibitControl>();
  std::shared_ptr<kiosk::RenderFrame> source = std::make_shared<kiosk::RenderFrame>(
      makeFrameSource(loaded, options, std::move(installation), control));
  kiosk::KioskLoop loop(
      loaded, [source](const kiosk::FrameRequest& r) { return (*source)(r); },
      [&] {
        kiosk::LoadedConfig reloaded = load();
        // Changed display settings need a fresh presenter, changed cameras or exhibit a fresh
        // frame loop. The old source goes first: two EGL presenters alive at once in one process
        // disturb each other's context.
        const auto changed = [&](const std::string& section) {
          return sectionText(reloaded.root, section) != sectionText(loaded.root, section);
        };
        const bool playlist_only = !changed("display") && !changed("capture") && changed("exhibit") &&
                                   exhibitSettingsText(reloaded.root) == exhibitSettingsText(loaded.root) &&
                                   describesPlaylist(loaded.root) && describesPlaylist(reloaded.root) &&
                                   installation && !installation->playlist.empty();
        if (playlist_only) {
          HOLO_LOG_INFO("exhibit playlist changed: the running frame source takes it");
          control->replace(std::move(installation->playlist), std::move(installation->exhibit_problems));
          installation.reset();
        } else if (changed("display") || changed("capture") || changed("exhibit")) {
          HOLO_LOG_INFO("display, camera or exhibit settings changed: restarting the frame source");
          *source = {};
          *source = makeFrameSource(reloaded, options, std::move(installation), control);
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
      sub.add_option("--config", options->config,
                     "YAML configuration (kiosk:, display:, and capture: and exhibit: for real cameras)")
          ->capture_default_str();
      sub.add_flag("--headless", options->headless, "Render offscreen through EGL, no windows");
      sub.add_flag("--relearn-background", options->relearn_background,
                   "Learn the background from the first frames even when the calibration captured one");
      sub.add_option("--source", options->source,
                     "pipeline (the product) | test-pattern (the alignment pattern, for supervision checks)")
          ->check(CLI::IsMember({"pipeline", "test-pattern"}))
          ->capture_default_str();
      sub.add_option(
             "--scene", options->scene,
             "Scene of the simulated museum the pipeline shows when the configuration names no cameras")
          ->capture_default_str();
      sub.add_option("--view-size", options->view_size,
                     "Pixels of each square face view at full quality (pipeline source); 0: the size "
                     "the screen shows a face at (a Full HD cross: 360)")
          ->check(CLI::Range(0, 4096))
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
