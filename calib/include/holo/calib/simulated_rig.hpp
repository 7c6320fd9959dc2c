// The calibration rig of the simulated museum: its four cameras photograph synthetic boards
// composited over their view of the hall, deliver the empty hall as background frames, and the
// simulated monitors show the test pattern with a known misalignment. Everything is seeded, and
// the truth (intrinsics, poses, panorama yaw, face alignment) is exposed for checking.
#pragma once

#include <map>
#include <memory>
#include <mutex>

#include "holo/calib/auto_calibration.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/sim/museum.hpp"

namespace holo::calib {

class SimulatedRig : public CalibrationRig {
 public:
  // `scene`: a built-in scene name or scene file (holo::sim::loadScene).
  SimulatedRig(const std::string& scene, const AutoCalibrationConfig& config);

  int cameraCount() const override;
  std::string serial(int camera) const override;
  cv::Size imageSize(int camera) const override;
  int intrinsicsViewCount() const override { return 16; }
  cv::Mat intrinsicsPhoto(int camera, int view) const override;
  cv::Mat placementPhoto(int camera) const override;
  RgbdFrame backgroundFrame(int camera, int index) const override;
  cv::Mat panorama() const override;
  std::vector<cv::Point2f> observedTestPattern(int face, cv::Size view) const override;

  // The truth the calibration should recover.
  const CameraModel& trueCamera(int camera) const;
  float truePanoramaYaw() const { return panorama_yaw_; }
  FaceAlignment trueFaceAlignment(int face) const;

 private:
  cv::Mat hallView(int camera) const;  // the camera's colour view of the empty hall (cached)

  sim::Museum museum_;
  AutoCalibrationConfig config_;
  BoardTexture intrinsics_texture_;
  BoardTexture placement_texture_;
  float panorama_yaw_ = 0.0f;
  int panorama_shift_px_ = 0;
  mutable std::mutex cache_mutex_;
  mutable std::map<int, cv::Mat> hall_views_;
};

}  // namespace holo::calib
