// Ties systemd's watchdog to real frame progress. The frame loop calls frameCompleted() after
// each presented frame; the watchdog pets systemd (WATCHDOG=1) from that call, at most once per
// pet interval (half of WatchdogSec, as sd_watchdog_enabled(3) recommends). There is no timer
// thread on purpose: a render that hangs stops calling frameCompleted(), the pings stop, and
// systemd restarts the service after WatchdogSec, which is exactly the fault we want caught.
//
// Pure logic with the time passed in, so tests need no clock.
#pragma once

#include <chrono>
#include <functional>
#include <optional>

namespace holo::kiosk {

class FrameWatchdog {
 public:
  using Clock = std::chrono::steady_clock;
  // `pet` sends WATCHDOG=1; `timeout` is WatchdogSec (none: the watchdog is off and pet is
  // never called, but progress is still tracked for the health report).
  FrameWatchdog(std::optional<std::chrono::microseconds> timeout, std::function<void()> pet);

  // A frame was presented at `now`; pets when the interval since the last pet has passed.
  // Returns true when it petted.
  bool frameCompleted(Clock::time_point now);

  // Seconds since the last completed frame (0 before the first frame, which has its own
  // start-up allowance in systemd's TimeoutStartSec).
  double secondsSinceProgress(Clock::time_point now) const;
  std::optional<std::chrono::microseconds> petInterval() const { return interval_; }
  long pets() const { return pets_; }
  long frames() const { return frames_; }

 private:
  std::optional<std::chrono::microseconds> interval_;
  std::function<void()> pet_;
  std::optional<Clock::time_point> last_pet_;
  std::optional<Clock::time_point> last_frame_;
  long pets_ = 0;
  long frames_ = 0;
};

}  // namespace holo::kiosk
