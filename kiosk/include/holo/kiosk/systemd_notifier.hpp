// The service manager's side channel (sd_notify(3)). Under systemd with Type=notify the unit
// sets NOTIFY_SOCKET and, with WatchdogSec=, WATCHDOG_USEC; outside systemd every call is a
// cheap no-op, so the kiosk runs the same from a terminal.
//
// Protocol the kiosk follows:
//   READY=1        once, after the first frame is on screen (and again after each reload);
//   WATCHDOG=1     from the frame loop's progress only (FrameWatchdog), never from a timer alone;
//   STATUS=...     one-line health summary, whenever it changes;
//   RELOADING=1    when SIGHUP starts a config reload (followed by READY=1 when done);
//   STOPPING=1     when SIGTERM starts the clean stop.
#pragma once

#include <chrono>
#include <optional>
#include <string>

namespace holo::kiosk {

class SystemdNotifier {
 public:
  // Reads NOTIFY_SOCKET / WATCHDOG_USEC / WATCHDOG_PID once (sd_watchdog_enabled).
  SystemdNotifier();

  // True when a notification socket is configured (running under systemd or a test).
  bool enabled() const { return enabled_; }
  // The watchdog timeout systemd expects us to beat (WatchdogSec), when enabled for this pid.
  std::optional<std::chrono::microseconds> watchdogTimeout() const { return watchdog_timeout_; }

  void ready(const std::string& status);
  void watchdog();
  void status(const std::string& status);
  void reloading();
  void stopping();

  // Messages actually sent (for STATUS deduplication and diagnostics).
  long sentCount() const { return sent_; }

 private:
  void send(const std::string& message);
  bool enabled_ = false;
  std::optional<std::chrono::microseconds> watchdog_timeout_;
  std::string last_status_;
  long sent_ = 0;
};

}  // namespace holo::kiosk
