// What the calibration steps need from the appliance: each camera's frames as they arrive while
// the technician works (a board moved in front of a camera, the easel at the marked spots, the
// empty hall), the hall's panorama, and where the test pattern's dots were seen on each face.
// Live cameras (capture_rig.hpp: Aravis, V4L2, recordings, photo folders) and the simulated
// museum (simulated/simulated_rig.hpp) both provide it; the steps (calibration_session.hpp) decide, frame by
// frame, which frames to keep.
//
// Invariants: nextFrame() is called from one thread at a time (the step being measured); frames of
// one camera come in time order.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/rgbd_frame.hpp"

namespace holo::calib {

// What the technician is asked to do while a step takes frames.
enum class RigActivity {
  HandHeldBoard,    // the intrinsics board moved and tilted in front of each camera
  PlacementBoard,   // the placement board on the easel at each marked spot in turn
  EmptyHall,        // nobody and nothing in front of the cameras
  VerificationJig,  // the verification jig on the base's sides (verification_target.hpp), nobody in front
};

class CalibrationRig {
 public:
  virtual ~CalibrationRig() = default;
  virtual int cameraCount() const = 0;
  virtual std::string serial(int camera) const = 0;
  virtual cv::Size imageSize(int camera) const = 0;
  // Where the frames come from, for titles and logs ("simulated museum (scene museum)").
  virtual std::string describe() const = 0;

  // A step starts asking for frames of `activity`. Live cameras ignore it (the technician reads
  // the step's instructions on screen); the simulated technician starts acting it out.
  virtual void begin(RigActivity activity) { (void)activity; }
  // The next frame of `camera` (colour BGR 8-bit; depth in metres where the camera has it), or
  // nothing once the camera has no more frames (the end of a recording or of a photo folder).
  // Throws InputError when a live camera stops delivering.
  virtual std::optional<RgbdFrame> nextFrame(int camera) = 0;
  // True when consecutive frames are unrelated stills (photos): no frame can be compared with the
  // previous one to tell whether the board was held still.
  virtual bool stills() const { return false; }

  // The depth device's nominal metres per raw unit (the scale its depth frames were converted
  // with); the depth registration fits the true one relative to it.
  virtual double metresPerDepthUnit(int camera) const {
    (void)camera;
    return 0.001;
  }

  virtual cv::Mat panorama() const = 0;  // CV_32FC3 linear BGR, equirectangular
  // Where each dot of testPatternDots(view) appeared on face `face` (screen pixels).
  virtual std::vector<cv::Point2f> observedTestPattern(int face, cv::Size view) const = 0;
};

}  // namespace holo::calib
