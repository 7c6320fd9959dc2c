// A camera that costs the host nothing to produce its frames, as a real one: `bench frame --live`
// records a loop of frames from a (simulated) source before the run and hands them out at the
// camera's rate on its capture thread, each stamped when it is delivered (host_time, the arrival
// the loop's latency is measured from). Frame n is recorded frame n mod count, delivered no earlier
// than n / fps after start(), its pixels shared with the recording (frames are values, rgbd_frame.hpp).
// Units: frames per second; nanoseconds for the grab timeout.
#pragma once

#include <memory>
#include <vector>

#include "holo/capture/camera_source.hpp"

namespace holo::eval {

class ReplayedSource final : public capture::CameraSource {
 public:
  // Opens `recorded`, grabs `frames` (> 0) frames from it and stops it. Throws Error when it
  // gives fewer.
  ReplayedSource(std::unique_ptr<capture::CameraSource> recorded, int frames, double fps);

  std::string name() const override { return "replayed:" + recorded_name_; }
  std::string serial() const override { return serial_; }
  void open() override {}
  void start() override;
  void stop() override {}
  capture::GrabResult grab(Nanoseconds timeout) override;
  std::optional<CameraModel> cameraModel() const override { return model_; }
  double metresPerDepthUnit() const override { return metres_per_unit_; }

 private:
  std::string recorded_name_, serial_;
  std::optional<CameraModel> model_;
  double metres_per_unit_ = 0.001;
  std::vector<RgbdFrame> frames_;
  double fps_;
  std::int64_t next_ = 0;
  Clock::time_point start_;
};

}  // namespace holo::eval
