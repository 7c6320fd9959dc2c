// Every calibration step in order, without a window (`holopyramid calibrate --auto`, scripts and
// tests): intrinsics from board photos, each camera's pose from boards at known placements,
// background capture, panorama yaw, display alignment; each step prints its quality figure and a
// pass/fail verdict with a hint, and the results are saved atomically (camera_SERIAL.yml per
// camera, pyramid.yml, background PNGs and detection pictures) into one folder.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "holo/calib/calibration_plan.hpp"
#include "holo/calib/calibration_rig.hpp"

namespace holo::calib {

// Runs the steps, a line per step (and hints) to `log`; saves into `out_dir` only when every
// step passed. Otherwise nothing is written (the previous calibration stays in force) and the
// report says why: a step that could not be measured at all rethrows its InputError.
AutoCalibrationReport runAutoCalibration(CalibrationRig& rig, const AutoCalibrationConfig& config,
                                         const std::filesystem::path& out_dir, std::ostream& log,
                                         bool quiet = false);

}  // namespace holo::calib
