#include "holo/capture/camera_source.hpp"

namespace holo::capture {

const char* toString(GrabStatus status) {
  switch (status) {
    case GrabStatus::Ok:
      return "ok";
    case GrabStatus::Timeout:
      return "timeout";
    case GrabStatus::Incomplete:
      return "incomplete";
    case GrabStatus::Failed:
      return "failed";
    case GrabStatus::Disconnected:
      return "disconnected";
    case GrabStatus::EndOfStream:
      return "end of stream";
  }
  return "unknown";
}

CameraHealth HealthCounters::snapshot(Clock::time_point now) const {
  CameraHealth h;
  h.frames_completed = frames_completed.load(std::memory_order_relaxed);
  h.frames_failed = frames_failed.load(std::memory_order_relaxed);
  h.frames_timed_out = frames_timed_out.load(std::memory_order_relaxed);
  h.frames_incomplete = frames_incomplete.load(std::memory_order_relaxed);
  h.resends = resends.load(std::memory_order_relaxed);
  h.disconnects = disconnects.load(std::memory_order_relaxed);
  h.reconnects = reconnects.load(std::memory_order_relaxed);
  h.frames_unpaired = frames_unpaired.load(std::memory_order_relaxed);
  h.pair_skew_ms = static_cast<double>(pair_skew_us.load(std::memory_order_relaxed)) * 1e-3;
  h.connected = connected.load(std::memory_order_relaxed);
  const std::int64_t last = last_frame_ns.load(std::memory_order_relaxed);
  if (last >= 0) {
    const auto age = now.time_since_epoch() - Clock::duration(last);
    h.last_frame_age_s = std::chrono::duration<double>(age).count();
  }
  return h;
}

}  // namespace holo::capture
