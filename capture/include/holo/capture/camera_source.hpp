// One camera behind one interface, whatever it is (Aravis, V4L2, a recording, the simulated
// museum). Lifecycle: open() -> start() -> grab()... -> stop(); open() may be called again after
// stop() to reconnect. A source is used by one thread at a time (its CaptureThread); only the
// health counters are read from other threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::capture {

// What one grab() gave. Only Ok carries a frame.
enum class GrabStatus {
  Ok,            // a complete frame
  Timeout,       // nothing arrived within the timeout; the camera may still be there
  Incomplete,    // a buffer arrived with missing packets; it was counted and re-queued, not used
  Failed,        // the device reported an error for this frame; streaming goes on
  Disconnected,  // the device is gone; the caller stops the source and reconnects
  EndOfStream,   // a finite source (a recording) has no more frames
};
const char* toString(GrabStatus status);

struct GrabResult {
  GrabStatus status = GrabStatus::Timeout;
  RgbdFrame frame;      // valid when status == Ok
  std::string message;  // why, for anything but Ok
};

// A copy of a camera's health counters at one moment.
struct CameraHealth {
  std::int64_t frames_completed = 0;
  std::int64_t frames_failed = 0;
  std::int64_t frames_timed_out = 0;
  std::int64_t frames_incomplete = 0;  // buffers with missing packets, dropped and re-queued
  std::int64_t resends = 0;            // packets the device re-sent on request (GigE Vision)
  std::int64_t disconnects = 0;        // times the source was lost
  std::int64_t reconnects = 0;         // times it came back after a loss
  // Two-device cameras (frame_pairing.hpp): colour and depth frames dropped for want of a
  // partner within the pairing tolerance, and the last pair's depth - colour arrival time.
  std::int64_t frames_unpaired = 0;
  double pair_skew_ms = 0.0;
  bool connected = false;
  double last_frame_age_s = -1.0;  // seconds since the last complete frame; -1 = never
};

// Live counters: atomics written by the capture thread (and the source), read from anywhere.
class HealthCounters {
 public:
  std::atomic<std::int64_t> frames_completed{0};
  std::atomic<std::int64_t> frames_failed{0};
  std::atomic<std::int64_t> frames_timed_out{0};
  std::atomic<std::int64_t> frames_incomplete{0};
  std::atomic<std::int64_t> resends{0};
  std::atomic<std::int64_t> disconnects{0};
  std::atomic<std::int64_t> reconnects{0};
  std::atomic<std::int64_t> frames_unpaired{0};
  std::atomic<std::int64_t> pair_skew_us{0};
  std::atomic<bool> connected{false};
  std::atomic<std::int64_t> last_frame_ns{-1};  // steady_clock time of the last complete frame

  void markFrame(Clock::time_point when) {
    frames_completed.fetch_add(1, std::memory_order_relaxed);
    last_frame_ns.store(when.time_since_epoch().count(), std::memory_order_relaxed);
  }
  CameraHealth snapshot(Clock::time_point now = Clock::now()) const;
};

class CameraSource {
 public:
  virtual ~CameraSource() = default;

  // Human-readable name ("aravis:Fake_GV01", "recording:cam0") and the device serial ("" when the
  // source has none). Both are valid before open().
  virtual std::string name() const = 0;
  virtual std::string serial() const = 0;

  // Connects to the device. Throws holo::InputError for a configuration the device cannot do
  // (unknown serial, unsupported format) and holo::Error when it is not reachable now.
  virtual void open() = 0;
  virtual void start() = 0;
  // Stops streaming and releases the device; safe to call in any state, never throws.
  virtual void stop() = 0;
  // Waits at most `timeout` for the next frame. Frames carry sequence, device_time and host_time;
  // camera_id is set by the capture thread.
  virtual GrabResult grab(Nanoseconds timeout) = 0;

  // Intrinsics and pose when the source knows them (a recording, the simulation).
  virtual std::optional<CameraModel> cameraModel() const { return std::nullopt; }
  // The metres per raw depth unit the source converts its depth with (its configured or
  // recorded scale); a calibration that fitted the camera's true scale corrects by the ratio.
  // Simulated cameras model millimetre sensors.
  virtual double metresPerDepthUnit() const { return 0.001; }

  HealthCounters& health() { return health_; }
  const HealthCounters& health() const { return health_; }

 private:
  HealthCounters health_;
};

}  // namespace holo::capture
