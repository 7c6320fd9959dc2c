// `holopyramid calibrate wizard [--scene museum | --config FILE] [--out DIR]` opens the calibration
// wizard on the simulated museum or on the cameras of a configuration's capture: section.
// `--script next,back,retry,...` presses its buttons in order (each once the step on screen has
// finished measuring) and `--screenshot-dir DIR` writes the window as each step looks just before
// a scripted press (wizard_N_STEP.png, the last press on a step wins) and once while it measures
// (wizard_N_STEP_measuring.png): the docs' pictures and the Xvfb test come from these. Exit code 0 when the
// calibration was saved with every step passed, 3 otherwise, 2 on bad input.
#include "command.hpp"

#include <iostream>
#include <memory>
#include <sstream>

#include "holo/calib/calibration_wizard.hpp"
#include "holo/calib/capture_rig.hpp"
#include "holo/core/error.hpp"
#include "holo/simulated/simulated_rig.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;
using Button = calib::CalibrationWizard::Button;

struct WizardOptions {
  std::string scene = "museum";
  std::string config;
  std::string out;
  std::string intrinsics_board = calib::kDefaultIntrinsicsBoard;
  std::string placement_board = calib::kDefaultPlacementBoard;
  int background_frames = 9;
  std::string script;
  std::string screenshot_dir;
};

std::vector<Button> parseScript(const std::string& script) {
  std::vector<Button> buttons;
  std::stringstream in(script);
  std::string word;
  while (std::getline(in, word, ',')) {
    bool known = false;
    for (const Button b : {Button::Back, Button::Retry, Button::Next, Button::Save, Button::Close})
      if (word == buttonName(b)) {
        buttons.push_back(b);
        known = true;
      }
    if (!known)
      throw InputError("--script", "action " + std::to_string(buttons.size() + 1),
                       "back, retry, next, save or close", word);
  }
  return buttons;
}

std::string screenshotName(int index, calib::CalibrationStep step) {
  std::string slug = calib::stepTitle(step);
  for (char& ch : slug)
    if (ch == ' ') ch = '_';
  return "wizard_" + std::to_string(index) + "_" + slug + ".png";
}

// Draws frames until the step on screen has finished measuring, then a few more so the finished
// step's layout has settled (ImGui sizes some items from the previous frame). With `screenshots`,
// the window is also saved once mid-measurement, when two cameras' live pictures are on screen
// (wizard_N_STEP_measuring.png; quick steps may finish before).
void settle(calib::CalibrationWizard& wizard, const std::string& screenshots) {
  bool measuring_shot = screenshots.empty();
  while (wizard.busy()) {
    if (!measuring_shot && wizard.livePictureCount() >= 2) {
      fs::path png =
          fs::path(screenshots) / screenshotName(static_cast<int>(wizard.step()) + 1, wizard.step());
      png.replace_filename(png.stem().string() + "_measuring.png");
      if (!wizard.frame(png)) return;
      measuring_shot = true;
    } else if (!wizard.frame()) {
      return;
    }
  }
  for (int k = 0; k < 3; ++k) wizard.frame();
}

}  // namespace

calib::AutoCalibrationConfig calibrationConfig(const std::string& intrinsics_board,
                                               const std::string& placement_board, int background_frames) {
  calib::AutoCalibrationConfig config;
  config.intrinsics_board = calib::BoardSpec::parse(intrinsics_board, "--intrinsics-board");
  config.placement_board = calib::BoardSpec::parse(placement_board, "--placement-board");
  if (background_frames < 1)
    throw InputError("--background-frames", "frames", "at least 1", std::to_string(background_frames));
  config.background_frames = background_frames;
  config.placements = calib::defaultBoardPlacements(config.placement_board, sim::kFaceCount);
  return config;
}

namespace {

int runWizard(const WizardOptions& options) {
  const calib::AutoCalibrationConfig base =
      calibrationConfig(options.intrinsics_board, options.placement_board, options.background_frames);
  const std::vector<Button> script = parseScript(options.script);
  // The simulated museum, or the cameras of --config's capture: section.
  std::unique_ptr<calib::CalibrationRig> rig;
  fs::path out = options.out.empty() ? fs::path("calibration") : fs::path(options.out);
  calib::AutoCalibrationConfig config = base;
  if (!options.config.empty()) {
    calib::ConfiguredRig configured =
        calib::loadConfiguredRig(options.config, simulated::configuredSources());
    if (options.out.empty()) out = configured.calibration_dir;
    config.placements = calib::defaultBoardPlacements(config.placement_board, configured.rig->cameraCount());
    rig = std::move(configured.rig);
  } else {
    rig = std::make_unique<simulated::SimulatedRig>(options.scene, config);
  }
  calib::CalibrationSession session(*rig, config);
  calib::CalibrationWizard wizard(session, {out, rig->describe()});
  if (script.empty()) {
    while (wizard.frame()) {
    }
  } else {
    for (std::size_t i = 0; i < script.size(); ++i) {
      settle(wizard, options.screenshot_dir);
      if (!options.screenshot_dir.empty())
        wizard.frame(fs::path(options.screenshot_dir) /
                     screenshotName(static_cast<int>(wizard.step()) + 1, wizard.step()));
      wizard.press(script[i], "--script action " + std::to_string(i + 1));
      wizard.frame();
    }
    settle(wizard, options.screenshot_dir);
  }
  std::cout << wizard.log();
  const calib::AutoCalibrationReport report = session.report();
  std::cout << "verdicts:\n";
  for (const calib::StepVerdict& verdict : report.verdicts)
    std::cout << calib::formatVerdict(verdict) << "\n";
  std::cout << (wizard.saved() ? "saved into " + out.string()
                               : "closed without saving: the previous calibration in " + out.string() +
                                     " stays in force")
            << "\n";
  return wizard.saved() && report.allPassed() ? 0 : 3;
}

}  // namespace

WizardSubcommand addWizardSubcommand(CLI::App& calibrate) {
  auto options = std::make_shared<WizardOptions>();
  CLI::App* sub = calibrate.add_subcommand(
      "wizard", "Open the calibration wizard window (on the simulated museum, or the cameras of --config)");
  sub->add_option("--config", options->config,
                  "YAML configuration: calibrate the cameras of its capture: section");
  sub->add_option("--scene", options->scene, "Simulated scene (without --config)")->capture_default_str();
  sub->add_option("--out", options->out,
                  "Folder Save writes the calibration into (default: capture.calibration_dir of --config, "
                  "else calibration)");
  sub->add_option("--intrinsics-board", options->intrinsics_board, "Board for intrinsics")
      ->capture_default_str();
  sub->add_option("--placement-board", options->placement_board, "Board at the marked placements")
      ->capture_default_str();
  sub->add_option("--background-frames", options->background_frames, "Frames per background")
      ->capture_default_str();
  sub->add_option("--script", options->script,
                  "Press these buttons in order, each once the step has been measured: "
                  "comma-separated back, retry, next, save, close");
  sub->add_option("--screenshot-dir", options->screenshot_dir,
                  "With --script: write the window as each step looks before a press (PNG)");
  return {sub, [options] { return runWizard(*options); }};
}

}  // namespace holo::app
