// `holopyramid calibrate wizard`: the calibration wizard window on the simulated museum (real
// cameras join when the capture module provides a calibration rig). A subcommand of
// `calibrate`, so cmd_calibrate.cpp adds it and runs it when parsed.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "holo/calib/auto_calibration.hpp"

namespace holo::app {

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

}  // namespace holo::app
