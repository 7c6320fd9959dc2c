// Subcommands of the `holopyramid` program. Each app/cmd_*.cpp file registers its subcommand
// with a static HOLO_REGISTER_COMMAND; main() builds the CLI11 tree from the registry (a name
// with a space, "eval depth", lands under the group "eval"). A
// command's run function returns the process exit code; InputError and Error thrown from it are
// reported as one line on stderr with exit code 2 and 1.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "holo/calib/auto_calibration.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::app {

struct Command {
  std::string name;
  // Adds the subcommand's options to `sub`; returns the function that runs it once parsed.
  std::function<std::function<int()>(CLI::App& sub)> setup;
  std::string description;
};

bool registerCommand(Command command);

// `calibrate wizard` (cmd_calibrate_wizard.cpp) is a subcommand of `calibrate` (cmd_calibrate.cpp):
// that one adds it and runs it when parsed.
struct WizardSubcommand {
  CLI::App* app = nullptr;  // parsed() when the command line chose the wizard
  std::function<int()> run;
};

WizardSubcommand addWizardSubcommand(CLI::App& calibrate);

// What `calibrate --auto` and the wizard share: the boards from their command-line specs
// (InputError naming the flag otherwise), the background frame count (>= 1) and the default
// board placements in front of the four faces.
calib::AutoCalibrationConfig calibrationConfig(const std::string& intrinsics_board,
                                               const std::string& placement_board, int background_frames);

// --panorama-at-infinity, for every command that renders a hall's reflections.
inline void addPanoramaAtInfinityFlag(CLI::App& app, bool& at_infinity) {
  app.add_flag(
      "--panorama-at-infinity", at_infinity,
      "The reflections read the hall's panorama at infinity from its capture point, not through the "
      "hall's proxy (its distance and the pyramid's base: the simulated hall's, or exhibit.hall_radius "
      "and base_half_width; for comparisons with figures taken that way)");
}

// When the live loop traces a view's static passes again: --static-reuse, --static-retraces,
// --static-defer, for the commands that run it.
inline void addStaticReuseOptions(CLI::App& app, reflect::TracerSettings& tracer) {
  app.add_option("--static-reuse", tracer.static_reuse_distance,
                 "Metres an eye may move before a view's hit points are traced again (0: identical only)")
      ->capture_default_str();
  app.add_option("--static-retraces", tracer.static_retraces_per_frame,
                 "Views whose eye moved that trace again in one frame; the others show their last trace "
                 "a frame more (0: every one)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--static-defer", tracer.static_defer_distance,
                 "Metres an eye may move before its view traces again whatever --static-retraces leaves")
      ->capture_default_str();
}

// When the live loop takes its camera frames, shared by `run` and `bench frame`.
inline void addCameraTimingOptions(CLI::App& app, pipeline::FrameLoopOptions& loop) {
  app.add_flag("!--no-overlap", loop.overlap,
               "Compute each frame's foreground after the previous frame instead of during it");
  app.add_option("--fresh-frame-wait", loop.fresh_frame_wait_ms,
                 "Live: milliseconds the foreground step waits for a camera frame predicted to arrive "
                 "within them (0: never waits)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
}

// The options of the evaluation scene and view, shared by `render`, `eval reflections` and the
// evaluations built on them.
inline void addSceneOptions(CLI::App& app, eval::SceneOptions& options) {
  app.add_option("--scene", options.scene, "Built-in scene name or YAML file; 'empty' = relic alone")
      ->capture_default_str();
  app.add_option("--relic", options.relic, "Built-in relic name or glTF file (default: the scene's)");
  app.add_option("--hall", options.hall,
                 "Built-in hall (room, gallery, atrium, window) instead of the scene's");
  app.add_option("--panorama", options.panorama,
                 "HDR/EXR panorama (default: the museum hall rendered from the pyramid)");
  app.add_flag("--fit", options.fit, "Scale and centre a relic file on the pedestal");
  app.add_option("--frame", options.frame, "Museum frame (visitor poses)")->capture_default_str();
  app.add_option("--close-visitors", options.close_visitors,
                 "Visitors standing close to the pyramid, reaching out to it (default: the scene's)")
      ->check(CLI::Range(0, 4));
  app.add_option("--visitor-model", options.visitor_model,
                 "Visitors instead of the scene's: bodies (the default) or figures");
  addPanoramaAtInfinityFlag(app, options.panorama_at_infinity);
  app.add_option("--camera-vfov-deg", options.camera_vfov_deg,
                 "Depth cameras' vertical field of view, degrees (default: the scene's)")
      ->check(CLI::Range(10.0f, 170.0f));
  app.add_option("--camera-tilt-deg", options.camera_tilt_deg,
                 "Depth cameras' upwards tilt, degrees (default: the scene's)")
      ->check(CLI::Range(-60.0f, 60.0f));
}

inline void addViewOptions(CLI::App& app, eval::ViewOptions& options) {
  app.add_option("--width", options.width, "Image width, pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 8192));
  app.add_option("--height", options.height, "Image height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 8192));
  app.add_option("--face", options.face, "Pyramid face 0..3 (+Z, +X, -Z, -X)")
      ->capture_default_str()
      ->check(CLI::Range(0, 3));
  app.add_option("--eye", options.eye, "Explicit eye X,Y,Z (metres, world frame)");
  app.add_option("--look-at", options.look_at, "Explicit target X,Y,Z (default: the relic's centre)");
  app.add_option("--fov-deg", options.fov_deg, "Vertical field of view, degrees (default: frame the relic)");
}

}  // namespace holo::app

#define HOLO_CONCAT_INNER(a, b) a##b
#define HOLO_CONCAT(a, b) HOLO_CONCAT_INNER(a, b)
#define HOLO_REGISTER_COMMAND(...)                                    \
  static const bool HOLO_CONCAT(holo_command_registered_, __LINE__) = \
      ::holo::app::registerCommand(__VA_ARGS__)
