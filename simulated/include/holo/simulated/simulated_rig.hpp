// The calibration rig of the simulated museum: a simulated technician acts out what each step
// asks (begin()): moves the intrinsics board in front of each camera, holding it still at 16
// poses with a moving frame between them; stands the placement board on the easel at each marked
// spot in turn; clears the hall; mounts the verification jig (calib/verification_target.hpp). The four
// cameras film it over their view of the hall (frame(); the boards in colour and in depth), the simulated
// monitors show the test pattern with a known misalignment. Everything is seeded, and the truth (intrinsics,
// poses, panorama yaw, face alignment) is exposed for checking. `holopyramid simulate --calibration` records
// the same frames, so a calibration from that recording (calib/capture_rig.hpp) runs the very steps a
// calibration on this rig runs.
#pragma once

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

#include "holo/calib/auto_calibration.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/sim/museum.hpp"

namespace holo::simulated {

class SimulatedRig : public calib::CalibrationRig {
 public:
  // `scene`: a built-in scene name or scene file (holo::sim::loadScene).
  SimulatedRig(const std::string& scene, const calib::AutoCalibrationConfig& config);
  SimulatedRig(sim::SceneDescription scene, const calib::AutoCalibrationConfig& config);

  int cameraCount() const override;
  std::string serial(int camera) const override;
  cv::Size imageSize(int camera) const override;
  std::string describe() const override;
  void begin(calib::RigActivity activity) override;
  std::optional<RgbdFrame> nextFrame(int camera) override;
  cv::Mat panorama() const override;
  std::vector<cv::Point2f> observedTestPattern(int face, cv::Size view) const override;

  // The technician's session as frames: how many frames `activity` lasts (the same for every
  // camera) and frame `index` of `camera` during it (device_time counts from the activity's start
  // at the scene's frame rate).
  int frameCount(calib::RigActivity activity) const;
  RgbdFrame frame(calib::RigActivity activity, int camera, int index) const;

  // The depth device's frames lag the colour device's by `seconds` (>= 0): its picture of a
  // moving board shows the board further along (sim/device_errors.hpp). Default 0.
  void setDepthDelay(double seconds) { depth_delay_s_ = std::max(0.0, seconds); }
  // Camera `camera` was knocked after its pose was measured: the verification jig's frames show
  // it from T_world_camera * T_camera_knocked (camera-frame motion, metres). The hall behind the
  // jig stays as the camera saw it before (only the jig's edges are measured).
  void knockCamera(int camera, const cv::Matx44d& T_camera_knocked) { knocked_[camera] = T_camera_knocked; }

  // The truth the calibration should recover.
  const sim::Museum& museum() const { return museum_; }
  const CameraModel& trueCamera(int camera) const;
  float truePanoramaYaw() const { return panorama_yaw_; }
  calib::FaceAlignment trueFaceAlignment(int face) const;

 private:
  const RgbdFrame& hallFrame(int camera) const;  // the camera's frame of the empty hall (cached)
  RgbdFrame boardFrame(const calib::BoardTexture& texture, const Intrinsics& K,
                       const cv::Matx44d& T_camera_board, const cv::Matx44d& T_depth_board, int camera,
                       std::uint64_t seed, float blur) const;

  sim::Museum museum_;
  std::string scene_;
  calib::AutoCalibrationConfig config_;
  calib::BoardTexture intrinsics_texture_;
  calib::BoardTexture placement_texture_;
  calib::BoardTexture verification_texture_;
  float panorama_yaw_ = 0.0f;
  int panorama_shift_px_ = 0;
  double depth_delay_s_ = 0.0;
  std::map<int, cv::Matx44d> knocked_;
  calib::RigActivity activity_ = calib::RigActivity::HandHeldBoard;
  std::vector<int> next_;  // per camera: the next frame of the current activity
  mutable std::mutex cache_mutex_;
  mutable std::map<int, RgbdFrame> hall_frames_;
};

}  // namespace holo::simulated
