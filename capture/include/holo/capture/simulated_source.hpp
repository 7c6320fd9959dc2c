// One camera of the simulated museum (holo::sim::Museum) as a CameraSource. Frame n is the
// museum's frame n (time n / fps), so the content depends only on the scene, the camera and n:
// two runs give bit-identical frames whatever the timing. Paced sources hand out frame n no
// earlier than n / fps after start(), like a real camera; unpaced ones render as fast as they can
// (tests, offline recording). device_time is the scene time of the frame.
//
// The museum is shared (read-only) between the four sources of one scene; renderCamera is const
// and safe to call from several capture threads at once.
//
// Fault injection (the kiosk's tests and soak runs, never a configuration): setPowered(i, false)
// switches camera i of every simulated museum in the process off, as if its power were cut. It
// goes quiet (grab times out, so the capture thread declares it disconnected after its silence
// timeout) and open() fails until it is switched on again; then it restarts at first_frame, as a
// rebooted camera would.
#pragma once

#include <memory>

#include "holo/capture/camera_source.hpp"

namespace holo::sim {
class Museum;
}

namespace holo::capture {

struct SimulationOptions {
  bool paced = true;
  int first_frame = 0;
  int frame_count = -1;  // frames before EndOfStream; -1 = endless
  bool with_visitors = true;
};

class SimulatedSource : public CameraSource {
 public:
  // Throws InputError when `camera` is not 0..museum->cameraCount()-1.
  SimulatedSource(std::shared_ptr<const sim::Museum> museum, int camera, SimulationOptions options = {});

  std::string name() const override;    // "sim:<scene>/cam<i>"
  std::string serial() const override;  // "SIM-<scene>-<i>"
  // Throws InputError when `camera` is not 0..sim::kFaceCount-1. Thread-safe.
  static void setPowered(int camera, bool powered);
  static bool powered(int camera);

  void open() override;
  void start() override;
  void stop() override {}
  GrabResult grab(Nanoseconds timeout) override;
  std::optional<CameraModel> cameraModel() const override;

 private:
  std::shared_ptr<const sim::Museum> museum_;
  int camera_;
  SimulationOptions options_;
  int next_frame_ = 0;
  Clock::time_point start_;
};

}  // namespace holo::capture
