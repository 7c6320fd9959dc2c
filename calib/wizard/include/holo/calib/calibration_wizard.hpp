// The calibration wizard window (Dear ImGui on GLFW, OpenGL 3.3): walks a museum technician
// through the steps of a calib::CalibrationSession in order (intrinsics, camera poses, background,
// panorama yaw, display alignment, save). Each step shows what to do, the cameras' pictures as
// they arrive (detections drawn), every quality figure with its threshold and verdict, the hint
// of a failed one, and Back / Retry / Next buttons; Next stays disabled until the step passes, so
// only a calibration whose every step passed can be saved. Measuring runs on a worker thread so
// the window keeps drawing the live pictures.
//
// Scripts and tests press the same buttons with press(): the press is applied at the next frame
// by the code a mouse click runs.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "holo/calib/calibration_session.hpp"

namespace holo::calib {

struct WizardWindowOptions {
  std::filesystem::path out_dir;  // where Save writes the calibration
  std::string source;             // shown in the title: "simulated museum", a rig name
  int width = 1100;               // window size, screen pixels
  int height = 740;
};

class CalibrationWizard {
 public:
  enum class Button { Back, Retry, Next, Save, Close };

  // Opens the window and starts measuring the first step. Throws holo::Error when no window can
  // be opened (no DISPLAY, no OpenGL 3.3).
  CalibrationWizard(calib::CalibrationSession& session, WizardWindowOptions options);
  ~CalibrationWizard();
  CalibrationWizard(const CalibrationWizard&) = delete;
  CalibrationWizard& operator=(const CalibrationWizard&) = delete;

  // Draws one frame and handles input. Returns false once the window was closed (Close, Escape
  // or the window manager). With `screenshot`, writes the frame to that PNG as drawn.
  bool frame(const std::filesystem::path& screenshot = {});

  // Presses `button` at the next frame; throws InputError naming `source` when the button is
  // disabled now (a step measuring or failed, Save before the last step).
  void press(Button button, const std::string& source = "button");
  bool enabled(Button button) const;

  bool busy() const;  // a step is being measured
  // Cameras (faces) whose picture has arrived during the current measurement.
  int livePictureCount() const;
  calib::CalibrationStep step() const;
  bool saved() const;
  // What the steps measured, line by line (fx, poses, verdicts); empty while a step is measuring.
  std::string log() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

const char* buttonName(CalibrationWizard::Button button);

}  // namespace holo::calib
