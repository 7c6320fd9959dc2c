// One camera of the simulated museum (holo::sim::Museum) as a CameraSource. Frame n is the
// museum's frame n (time n / fps), so the content depends only on the scene, the camera and n:
// two runs give bit-identical frames whatever the timing. Paced sources hand out frame n no
// earlier than n / fps after start(), like a real camera; unpaced ones render as fast as they can
// (tests, offline recording). device_time is the scene time of the frame.
//
// The museum is shared (read-only) between the four sources of one scene; renderCamera is const
// and safe to call from several capture threads at once.
//
// Fault injection: a source honours the process's power switches (capture/camera_power.hpp) for
// its camera index. Switched off, it goes quiet and open() fails; switched on again, it restarts
// at first_frame, as a rebooted camera would.
//
// A configuration's `capture:` cameras of backend sim (capture_config.hpp) are built by
// configuredSources() below: capture parses them but does not link the simulation.
#pragma once

#include <memory>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_config.hpp"

namespace holo::sim {
class Museum;
}

namespace holo::simulated {

struct SimulationOptions {
  bool paced = true;
  int first_frame = 0;
  int frame_count = -1;  // frames before EndOfStream; -1 = endless
  bool with_visitors = true;
};

class SimulatedSource : public capture::CameraSource {
 public:
  // `camera`: a rig camera 0..museum->cameraCount()-1 or sim::Museum::kCheckCamera (named
  // "sim:<scene>/check"); anything else is an InputError.
  SimulatedSource(std::shared_ptr<const sim::Museum> museum, int camera, SimulationOptions options = {});

  std::string name() const override;    // "sim:<scene>/cam<i>"
  std::string serial() const override;  // "SIM-<scene>-<i>"
  void open() override;
  void start() override;
  void stop() override {}
  capture::GrabResult grab(Nanoseconds timeout) override;
  std::optional<CameraModel> cameraModel() const override;

 private:
  std::shared_ptr<const sim::Museum> museum_;
  int camera_;
  SimulationOptions options_;
  int next_frame_ = 0;
  Clock::time_point start_;
};

// Builds the sources of a configuration's simulated cameras (capture::Backend::Simulated) for
// capture::makeSources and the loaders that call it: cameras of the same scene share one museum,
// built once (by the first camera that names it) for the factory's lifetime.
capture::SourceFactory configuredSources();

}  // namespace holo::simulated
