#include "holo/kiosk/degradation_policy.hpp"

#include <cmath>

#include "holo/core/error.hpp"

namespace holo::kiosk {

const char* renderModeName(RenderMode mode) {
  switch (mode) {
    case RenderMode::Full:
      return "full";
    case RenderMode::Partial:
      return "partial";
    case RenderMode::IblOnly:
      return "ibl-only";
  }
  return "?";
}

DegradationPolicy::DegradationPolicy(DegradationSettings settings) : settings_(std::move(settings)) {
  const auto bad = [](const std::string& field, const std::string& expected) {
    throw InputError("", "kiosk.degradation." + field, expected);
  };
  if (settings_.quality_levels.empty()) bad("quality_levels", "at least one level");
  if (!(settings_.frame_budget_ms > 0.0)) bad("frame_budget_ms", "a positive number");
  if (!(settings_.headroom > 0.0 && settings_.headroom < 1.0)) bad("headroom", "a number in (0, 1)");
  if (!(settings_.smoothing > 0.0 && settings_.smoothing <= 1.0)) bad("smoothing", "a number in (0, 1]");
  if (settings_.down_after_frames < 1 || settings_.up_after_frames < 1 ||
      settings_.recover_after_frames < 1 || settings_.cooldown_frames < 0)
    bad("*_frames", "counts of at least 1 (cooldown at least 0)");
}

const std::string& DegradationPolicy::qualityName() const {
  return settings_.quality_levels[static_cast<std::size_t>(quality_)];
}

DegradationDecision DegradationPolicy::update(double frame_ms, int cameras_alive, int cameras_total) {
  DegradationDecision d;
  // --- quality from the frame time
  const double sample = std::isfinite(frame_ms) && frame_ms >= 0.0 ? frame_ms : 1e9;
  smoothed_ms_ = has_average_ ? smoothed_ms_ + settings_.smoothing * (sample - smoothed_ms_) : sample;
  has_average_ = true;
  const int last_level = static_cast<int>(settings_.quality_levels.size()) - 1;
  if (cooldown_ > 0) {
    // Right after a change the new level's times are still settling: do not count them.
    --cooldown_;
  } else if (smoothed_ms_ > settings_.frame_budget_ms) {
    ++over_frames_;
    under_frames_ = 0;
  } else if (smoothed_ms_ < settings_.headroom * settings_.frame_budget_ms) {
    ++under_frames_;
    over_frames_ = 0;
  } else {  // inside the hysteresis band: hold
    over_frames_ = 0;
    under_frames_ = 0;
  }
  if (over_frames_ >= settings_.down_after_frames && quality_ < last_level) {
    ++quality_;
    d.quality_changed = true;
  } else if (under_frames_ >= settings_.up_after_frames && quality_ > 0) {
    --quality_;
    d.quality_changed = true;
  }
  if (d.quality_changed) {
    over_frames_ = 0;
    under_frames_ = 0;
    cooldown_ = settings_.cooldown_frames;
    // The average still holds the old level's times; start the new level from the last sample.
    has_average_ = false;
  }

  // --- mode from the cameras
  RenderMode wanted = RenderMode::IblOnly;
  if (cameras_total > 0 && cameras_alive >= cameras_total)
    wanted = RenderMode::Full;
  else if (cameras_alive > 0)
    wanted = RenderMode::Partial;
  if (wanted > mode_) {  // worse: degrade at once
    mode_ = wanted;
    d.mode_changed = true;
    better_mode_frames_ = 0;
  } else if (wanted < mode_) {
    if (++better_mode_frames_ >= settings_.recover_after_frames) {
      mode_ = wanted;
      d.mode_changed = true;
      better_mode_frames_ = 0;
    }
  } else {
    better_mode_frames_ = 0;
  }
  d.quality = quality_;
  d.mode = mode_;
  return d;
}

}  // namespace holo::kiosk
