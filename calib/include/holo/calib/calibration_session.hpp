// A calibration in progress, one step at a time: what `calibrate --auto` runs in a row and the
// wizard window runs as the technician presses Next, Back and Retry. Each measuring step takes
// its pictures from the rig, computes its result with the step's math (intrinsics.hpp,
// extrinsics.hpp, background.hpp, panorama_alignment.hpp, display_alignment.hpp), judges it
// (quality.hpp) and keeps the pictures it saw with the detections drawn. Nothing is written until
// save(), which writes every file atomically into the output folder.
//
// Invariants: a step runs only after every earlier step has been measured (it builds on their
// results); measuring a step again forgets the outcomes of the steps after it.
#pragma once

#include <array>
#include <exception>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "holo/calib/auto_calibration.hpp"

namespace holo::calib {

enum class CalibrationStep { Intrinsics, Poses, Background, Panorama, Display, Save };
inline constexpr int kCalibrationSteps = 6;  // including Save
inline constexpr int kMeasuringSteps = 5;    // every step but Save

// Short name ("intrinsics", "camera poses", ...) and what the technician does in the step.
const char* stepTitle(CalibrationStep step);
const char* stepInstructions(CalibrationStep step);

struct StepOutcome {
  std::vector<StepVerdict> verdicts;  // one per camera (or face); one for the panorama
  // What the step saw, one picture per camera or face, BGR 8-bit with detections drawn.
  std::vector<std::pair<std::string, cv::Mat>> previews;
  // Files save() writes into the output folder (name, image): detection sheets, backgrounds.
  std::vector<std::pair<std::string, cv::Mat>> files;
  std::string error;             // set instead of verdicts when the step could not be measured at all
  std::exception_ptr exception;  // the InputError behind `error`, for callers that stop on it
  bool passed() const;
};

class CalibrationSession {
 public:
  // Receives each picture as soon as the rig delivers it (label, BGR image): live previews.
  using PreviewCallback = std::function<void(int index, const std::string& label, const cv::Mat& picture)>;

  CalibrationSession(const CalibrationRig& rig, AutoCalibrationConfig config);

  // Measures `step` (not Save). Errors of the input (too few views, no board) end up in the
  // outcome's `error`, as a failed step the technician can retry; they are not thrown.
  const StepOutcome& measure(CalibrationStep step, std::ostream& log, bool quiet = true,
                             const PreviewCallback& on_preview = {});
  // The outcome of `step`, when it has been measured since the steps before it last changed.
  const std::optional<StepOutcome>& outcome(CalibrationStep step) const;
  bool measured(CalibrationStep step) const { return outcome(step).has_value(); }

  // Writes camera_SERIAL.yml per camera, pyramid.yml and every step's pictures into `out_dir`
  // (each atomically, previous calibration files kept as .bak). Needs every step measured;
  // returns the files written.
  std::vector<std::filesystem::path> save(const std::filesystem::path& out_dir, std::ostream& log) const;

  // Every step's verdicts and the results so far (a report of a finished session).
  AutoCalibrationReport report() const;

 private:
  StepOutcome measureIntrinsics(std::ostream& log, bool quiet, const PreviewCallback& on_preview);
  StepOutcome measurePoses(std::ostream& log, const PreviewCallback& on_preview);
  StepOutcome measureBackground(std::ostream& log, bool quiet, const PreviewCallback& on_preview);
  StepOutcome measurePanorama(std::ostream& log, const PreviewCallback& on_preview);
  StepOutcome measureDisplay(std::ostream& log, const PreviewCallback& on_preview);

  const CalibrationRig& rig_;
  AutoCalibrationConfig config_;
  std::vector<CameraCalibration> cameras_;
  PyramidCalibration pyramid_;
  std::array<std::optional<StepOutcome>, kCalibrationSteps> outcomes_;
};

}  // namespace holo::calib
