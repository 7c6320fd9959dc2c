// The kiosk around a frame loop: it asks for frames, feeds their times and camera health to the
// degradation policy, blanks outside opening hours, pets systemd's watchdog only on presented
// frames, keeps the health JSON (file and loopback HTTP) and STATUS= current, and handles
// SIGHUP (reload) and SIGTERM (clean stop).
//
// The frame loop plugs in as one callback, RenderFrame: render and present one quad frame as
// the request says (quality level, camera mode, or black when blanked) and report what
// happened. The callback runs on the thread that called run() (GLFW needs the main thread).
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "holo/kiosk/degradation_policy.hpp"
#include "holo/kiosk/frame_watchdog.hpp"
#include "holo/kiosk/health_server.hpp"
#include "holo/kiosk/health_status.hpp"
#include "holo/kiosk/kiosk_action.hpp"
#include "holo/kiosk/kiosk_config.hpp"
#include "holo/kiosk/signal_events.hpp"
#include "holo/kiosk/systemd_notifier.hpp"

namespace holo::kiosk {

struct FrameRequest {
  std::int64_t index = 0;
  int quality = 0;  // 0 = best, see DegradationSettings::quality_levels
  std::string quality_name;
  RenderMode mode = RenderMode::Full;
  bool blank = false;                // outside opening hours: present black, skip the work
  std::vector<KioskAction> actions;  // asked for since the previous frame, oldest first
};

struct FrameReport {
  bool presented = false;                  // a frame reached the screen
  std::map<std::string, double> stage_ms;  // per stage, milliseconds
  std::vector<CameraHealth> cameras;       // one entry per configured camera (may be empty)
  std::optional<double> foreground_share;  // [0, 1]
  std::optional<double> camera_skew_ms;    // HealthStatus::camera_skew_ms
  std::vector<std::string> errors;         // faults of this frame, for the health JSON
  // The exhibit: the relic on screen and the one after it (names as the playlist gives them;
  // empty when unknown), and the playlist entries that could not be loaded, each "entry N (NAME):
  // why" (HealthStatus::relic, next_relic, exhibit_problems).
  std::string relic;
  std::string next_relic;
  std::vector<std::string> exhibit_problems;
};

using RenderFrame = std::function<FrameReport(const FrameRequest&)>;
// Called on SIGHUP: reload the configuration (with fallback) and reconfigure the frame source.
// Returns the configuration now in force.
using Reload = std::function<LoadedConfig()>;

class KioskLoop {
 public:
  KioskLoop(LoadedConfig config, RenderFrame render, Reload reload);
  ~KioskLoop();

  // Runs until SIGTERM/SIGINT (or `stop_after_frames` frames when > 0, for tests); returns the
  // process exit code (0 on a clean stop). Starts the health endpoint first.
  int run(SignalEvents& signals, SystemdNotifier& notifier, std::int64_t stop_after_frames = 0);

  // Thread-safe copy of the health, with uptime and time since the last frame filled in.
  HealthStatus health() const;
  // Port of the health endpoint (0 when none).
  std::uint16_t healthPort() const;

 private:
  void applyConfig(LoadedConfig config);
  void publish(SystemdNotifier& notifier, bool force);
  void frame(SystemdNotifier& notifier);

  LoadedConfig config_;
  RenderFrame render_;
  Reload reload_;
  std::unique_ptr<DegradationPolicy> policy_;
  std::unique_ptr<FrameWatchdog> watchdog_;
  std::unique_ptr<HealthServer> server_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point last_publish_{};
  std::chrono::steady_clock::time_point fps_window_start_{};
  std::int64_t fps_window_frames_ = 0;
  std::int64_t index_ = 0;
  bool ready_sent_ = false;
  bool was_blank_ = false;
  bool health_file_warned_ = false;
  int warmup_frames_left_ = 0;

  mutable std::mutex mutex_;  // guards health_ and last_frame_
  HealthStatus health_;
  std::optional<std::chrono::steady_clock::time_point> last_frame_;
};

}  // namespace holo::kiosk
