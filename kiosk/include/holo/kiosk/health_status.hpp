// What the kiosk knows about its own health, as JSON (file and HTTP endpoint) and as the one-line
// STATUS= summary systemd shows in `systemctl status`. Times in milliseconds, ages in seconds.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace holo::kiosk {

struct CameraHealth {
  std::string name;
  bool alive = false;           // delivered a fresh frame recently
  std::int64_t frames = 0;      // frames received since start
  std::int64_t dropped = 0;     // frames dropped (late, corrupt)
  std::int64_t reconnects = 0;  // times the source was reopened
  double last_frame_age_s = 0;  // seconds since its newest frame
  // Colour and depth from two devices: frames dropped for want of a partner in time, and the
  // last pair's depth - colour arrival time (capture/frame_pairing.hpp); 0 for one device.
  std::int64_t unpaired = 0;
  double pair_skew_ms = 0;
};

struct HealthStatus {
  std::string state = "starting";  // starting, running, blanked (closed hours), stopping
  std::string mode = "full";       // renderModeName
  std::string quality = "full";    // the degradation level's name
  int quality_level = 0;           // its index: 0 = best, higher = more degraded
  double frame_budget_ms = 0;      // kiosk.degradation.frame_budget_ms
  // The frame rate the kiosk aims at: kiosk.max_fps, or 1000 / frame_budget_ms when that is less.
  double target_fps = 0;
  double fps = 0;                          // over the last second or so
  double frame_ms = 0;                     // smoothed frame time
  std::map<std::string, double> stage_ms;  // last frame's stage times
  std::optional<double> foreground_share;  // fraction of view pixels showing foreground, [0, 1]
  // Spread of the arrival times of the camera frames the last frame was made of (newest - oldest,
  // ms): how far apart in time the cameras' views of a visitor are. None with fewer than 2 cameras.
  std::optional<double> camera_skew_ms;
  std::vector<CameraHealth> cameras;
  double uptime_s = 0;
  std::int64_t frames = 0;
  double seconds_since_frame = 0;             // grows when the frame loop hangs
  std::string config_source;                  // the file used, "last good copy" or "factory defaults"
  std::string config_warning;                 // why the configured file was not used (empty when it was)
  std::string relic;                          // the exhibit's relic on screen (FrameReport::relic)
  std::string next_relic;                     // the one after it
  std::vector<std::string> exhibit_problems;  // playlist entries skipped, each with why
  std::deque<std::string> last_errors;        // newest last, at most kMaxErrors

  static constexpr std::size_t kMaxErrors = 10;
  void addError(const std::string& message);
  int camerasAlive() const;

  nlohmann::json toJson() const;
  // The same figures in the Prometheus text exposition format 0.0.4, every metric prefixed
  // `holopyramid_`, in base units (seconds, not milliseconds), camera and stage names as escaped
  // label values; NaN and infinite figures as Prometheus spells them (NaN, +Inf, -Inf).
  std::string toPrometheus() const;
  // "cameras 3/4, 24.9 fps, fg 12%, mode partial, quality full[, CONFIG WARNING]"
  std::string summary() const;
};

}  // namespace holo::kiosk
