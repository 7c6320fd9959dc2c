// `holopyramid calibrate wizard`: the calibration wizard window on the simulated museum (real
// cameras join when the capture module provides a calibration rig). A subcommand of
// `calibrate`, so cmd_calibrate.cpp adds it and runs it when parsed.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace holo::app {

struct WizardSubcommand {
  CLI::App* app = nullptr;  // parsed() when the command line chose the wizard
  std::function<int()> run;
};

WizardSubcommand addWizardSubcommand(CLI::App& calibrate);

}  // namespace holo::app
