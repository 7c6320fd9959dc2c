// A calibration in progress, one step at a time: what `calibrate --auto` runs in a row and the
// wizard window runs as the technician presses Next, Back and Retry. Each measuring step takes
// frames from the rig as they arrive and decides which to keep, computes its result with the
// step's math (intrinsics.hpp, extrinsics.hpp, background.hpp, panorama_alignment.hpp,
// display_alignment.hpp), judges it (quality.hpp) and keeps the pictures it saw with the
// detections drawn. Nothing is written until save(), which writes every file atomically into the
// output folder.
//
// How the steps take frames (board_tracking.hpp):
//   intrinsics  camera by camera: the board is detected in every frame; a frame is kept when the
//               board is steady and the view adds pose diversity (coverage grid of the image and
//               of tilt); the camera is done when it has kIntrinsicsMinViews views and the board
//               has been gone for kBoardGoneFrames frames (or the frames end, or the budget). Per-view errors
//               are listed, outliers dropped (intrinsics.hpp). The same views then give, per
//               camera with depth, the depth registration (depth_registration.hpp: the board's
//               plane seen in colour and in depth; the fitted depth scale, and T_colour_depth when
//               it is distinguishable from identity) and, over all cameras, the colour gains
//               (colour_gains.hpp: the board's white and black squares), each with its verdicts.
//   poses       every camera's frames in step: the board is carried from marked spot to marked
//               spot in camera order; spot i is taken when camera i has seen it steady for
//               kPlacementSteadyFrames frames, the next spot is awaited once it has left camera
//               i's view. A camera j that sees the board at spot i at the same time gives the loop
//               closure: the relative pose of cameras i and j through the board must agree with
//               their calibrated poses.
//   background  the next background_frames frames of every camera.
//   verification  the first frame of every camera with the verification jig mounted
//               (verification_target.hpp): its printed squares projected through the camera's
//               calibration against the picture's edges (edge_alignment.hpp), the pose error
//               they show judged (quality.hpp).
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

#include "holo/calib/board_tracking.hpp"
#include "holo/calib/calibration_plan.hpp"
#include "holo/calib/calibration_rig.hpp"

namespace holo::calib {

enum class CalibrationStep { Intrinsics, Poses, Background, Panorama, Display, Verification, Save };
inline constexpr int kCalibrationSteps = 7;  // including Save
inline constexpr int kMeasuringSteps = 6;    // every step but Save

// Short name ("intrinsics", "camera poses", ...) and what the technician does in the step.
const char* stepTitle(CalibrationStep step);
const char* stepInstructions(CalibrationStep step);

inline constexpr int kBoardGoneFrames = 3;
inline constexpr int kPlacementSteadyFrames = 2;

// Two cameras that saw the placement board at once: the disagreement between their relative pose
// through the board (T_camera_i_board * T_camera_j_board^-1) and through their calibrated poses.
struct LoopClosure {
  int camera_i = 0;
  int camera_j = 0;
  int frames = 0;               // frames in which both saw the board
  double translation_mm = 0.0;  // worst over those frames
  double rotation_deg = 0.0;
};

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

  CalibrationSession(CalibrationRig& rig, AutoCalibrationConfig config);

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

  // The board in every frame the intrinsics step (camera by camera) or the poses step (the frames
  // in which the board was steady at a marked spot, every camera) took from `camera`, with its
  // pose in the camera frame once intrinsics are known. Empty before the step was measured.
  const std::vector<BoardFrameObservation>& boardObservations(CalibrationStep step, int camera) const;
  // The loop closures of the poses step (empty when no two cameras saw the board at once).
  const std::vector<LoopClosure>& loopClosures() const { return loop_closures_; }

 private:
  StepOutcome measureIntrinsics(std::ostream& log, bool quiet, const PreviewCallback& on_preview);
  // Depth registration and colour gains from the intrinsics step's kept views (cameras_ updated).
  void measureDepthAndColour(StepOutcome& out, std::ostream& log);
  StepOutcome measurePoses(std::ostream& log, const PreviewCallback& on_preview);
  StepOutcome measureBackground(std::ostream& log, bool quiet, const PreviewCallback& on_preview);
  StepOutcome measurePanorama(std::ostream& log, const PreviewCallback& on_preview);
  StepOutcome measureDisplay(std::ostream& log, const PreviewCallback& on_preview);
  StepOutcome measureVerification(std::ostream& log, const PreviewCallback& on_preview);

  CalibrationRig& rig_;
  AutoCalibrationConfig config_;
  std::vector<std::vector<BoardFrameObservation>> intrinsics_observations_;  // per camera
  std::vector<std::vector<BoardFrameObservation>> placement_observations_;   // per camera
  // Per camera: the frames the intrinsics step kept as views, with their detections.
  struct KeptView {
    RgbdFrame frame;
    BoardDetection detection;
  };
  std::vector<std::vector<KeptView>> intrinsics_views_;
  std::vector<LoopClosure> loop_closures_;
  std::vector<RgbdFrame> hall_frames_;  // per camera: the background step's first frame
  std::vector<CameraCalibration> cameras_;
  PyramidCalibration pyramid_;
  std::array<std::optional<StepOutcome>, kCalibrationSteps> outcomes_;
};

}  // namespace holo::calib
