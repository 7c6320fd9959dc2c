// Graceful degradation: the kiosk keeps a picture on screen whatever happens, trading quality
// for time and foreground for robustness. Two independent state machines, fed once per frame:
//
// Quality (frame time): levels 0..n-1, 0 the best (e.g. "full", "fewer passes", "half view
// resolution", "IBL at low resolution"; what a level means is the renderer's business). The
// frame time is smoothed (exponential average); when it stays over the budget for
// `down_after_frames` frames the level steps one down; when it stays under
// `headroom * budget` for `up_after_frames` frames it steps one up. The gap between budget and
// headroom, the longer wait upwards and a cooldown after every change are the hysteresis that
// stops the level from oscillating between two neighbours.
//
// Mode (cameras): full (every camera delivers), partial (some do: render with those),
// ibl-only (none does: static reflections only). A lost camera degrades at once; recovery
// needs the better state for `recover_after_frames` frames in a row, so a flapping cable does
// not flap the picture.
#pragma once

#include <string>
#include <vector>

namespace holo::kiosk {

enum class RenderMode { Full, Partial, IblOnly };
const char* renderModeName(RenderMode mode);  // "full", "partial", "ibl-only"

struct DegradationSettings {
  std::vector<std::string> quality_levels{"full", "reduced", "low", "minimal"};
  double frame_budget_ms = 40.0;  // 25 fps
  double headroom = 0.7;          // step up only below headroom * budget
  double smoothing = 0.2;         // weight of the newest frame in the average, (0, 1]
  int down_after_frames = 10;
  int up_after_frames = 60;
  int cooldown_frames = 30;       // no quality change right after one
  int recover_after_frames = 15;  // camera mode recovery
};

struct DegradationDecision {
  int quality = 0;  // index into quality_levels
  RenderMode mode = RenderMode::Full;
  bool quality_changed = false;
  bool mode_changed = false;
};

class DegradationPolicy {
 public:
  // Throws InputError("", "kiosk.degradation", ...) on settings that cannot work (no levels,
  // a non-positive budget, headroom outside (0, 1), smoothing outside (0, 1], counts < 1).
  explicit DegradationPolicy(DegradationSettings settings);

  // One frame: its total time in milliseconds (NaN/Inf/negative count as over budget, a broken
  // timer must degrade rather than hide an overload) and how many cameras delivered a fresh
  // frame out of how many are configured.
  DegradationDecision update(double frame_ms, int cameras_alive, int cameras_total);

  int quality() const { return quality_; }
  const std::string& qualityName() const;
  RenderMode mode() const { return mode_; }
  double smoothedFrameMs() const { return smoothed_ms_; }
  const DegradationSettings& settings() const { return settings_; }

 private:
  DegradationSettings settings_;
  int quality_ = 0;
  RenderMode mode_ = RenderMode::Full;
  double smoothed_ms_ = 0.0;
  bool has_average_ = false;
  int over_frames_ = 0;
  int under_frames_ = 0;
  int cooldown_ = 0;
  int better_mode_frames_ = 0;
};

}  // namespace holo::kiosk
