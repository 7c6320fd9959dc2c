// The kiosk around a frame loop: it asks for frames, feeds their times and camera health to the
// degradation policy, blanks outside opening hours, pets systemd's watchdog only on presented
// frames, keeps the health JSON (file and loopback HTTP) and STATUS= current, and handles
// SIGHUP (reload) and SIGTERM (clean stop). With kiosk.console enabled it also serves the
// technician's console (console_server.hpp), whose buttons reach the frame source as
// FrameRequest::actions (and "reload" takes the SIGHUP path), and whose snapshots the frame
// source takes only while a console client has asked for one in the last kSnapshotInterestS
// seconds, at most kSnapshotsPerSecond times a second: unwatched, the console costs the frame
// path nothing. JPEG encoding happens on the console's threads, never on the frame thread.
//
// The frame loop plugs in as one callback, RenderFrame: render and present one quad frame as
// the request says (quality level, camera mode, or black when blanked) and report what
// happened. The callback runs on the thread that called run() (GLFW needs the main thread).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/kiosk/console_auth.hpp"
#include "holo/kiosk/console_server.hpp"
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
  bool snapshot = false;             // a console client watches: fill FrameReport::snapshot
};

// The pictures of one frame for the console, 8-bit BGR; the frame source hands over images
// nobody writes to afterwards (copies, or images it never reuses). Empty Mats: no picture.
struct FrameSnapshot {
  std::array<cv::Mat, 4> faces;  // as presented
  std::vector<cv::Mat> cameras;  // each camera's colour image
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
  std::optional<FrameSnapshot> snapshot;  // when the request asked for one
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
  // Port of the console (0 when it is off or did not start).
  std::uint16_t consolePort() const;

  // Thread-safe (the console's handlers call them). An action reaches the next frame's request;
  // false when kMaxPendingActions are already waiting.
  bool requestAction(KioskAction action);
  // The configuration is reloaded as on SIGHUP, before the next frame.
  void requestReload();
  // The newest snapshot's JPEG (cameras scaled to at most 640 pixels wide), empty when there is
  // none yet; asking keeps snapshots coming for kSnapshotInterestS seconds.
  std::string snapshotJpeg(SnapshotKind kind, int index);

  static constexpr std::size_t kMaxPendingActions = 16;
  static constexpr double kSnapshotInterestS = 5.0;
  static constexpr double kSnapshotsPerSecond = 4.0;

 private:
  void applyConfig(LoadedConfig config);
  void publish(SystemdNotifier& notifier, bool force);
  void frame(SystemdNotifier& notifier);
  void reload(SystemdNotifier& notifier);
  void applyConsole(bool settings_changed);
  bool snapshotWanted(std::chrono::steady_clock::time_point now);

  LoadedConfig config_;
  RenderFrame render_;
  Reload reload_;
  std::unique_ptr<DegradationPolicy> policy_;
  std::unique_ptr<FrameWatchdog> watchdog_;
  std::unique_ptr<HealthServer> server_;
  std::shared_ptr<ConsoleAuth> console_auth_;
  std::unique_ptr<ConsoleServer> console_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point last_publish_{};
  std::chrono::steady_clock::time_point fps_window_start_{};
  std::int64_t fps_window_frames_ = 0;
  std::int64_t index_ = 0;
  bool ready_sent_ = false;
  bool was_blank_ = false;
  bool health_file_warned_ = false;
  int warmup_frames_left_ = 0;
  int cameras_alive_last_frame_ = -1;  // -1 before the first frame

  mutable std::mutex mutex_;  // guards health_ and last_frame_
  HealthStatus health_;
  std::optional<std::chrono::steady_clock::time_point> last_frame_;

  std::mutex actions_mutex_;  // guards pending_actions_
  std::deque<KioskAction> pending_actions_;
  std::atomic<bool> reload_requested_{false};

  // Snapshots: wanted until this steady-clock time (nanoseconds since its epoch); the newest one,
  // its number, and JPEGs already encoded from it.
  std::atomic<std::int64_t> snapshot_wanted_until_ns_{0};
  std::chrono::steady_clock::time_point last_snapshot_{};
  struct Jpeg {
    std::int64_t sequence = -1;
    std::string bytes;
  };
  std::mutex snapshot_mutex_;  // guards the three below
  std::shared_ptr<const FrameSnapshot> snapshot_;
  std::int64_t snapshot_sequence_ = 0;
  std::map<std::pair<SnapshotKind, int>, Jpeg> jpegs_;
};

}  // namespace holo::kiosk
