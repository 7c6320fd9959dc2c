#include "holo/kiosk/frame_watchdog.hpp"

namespace holo::kiosk {

FrameWatchdog::FrameWatchdog(std::optional<std::chrono::microseconds> timeout, std::function<void()> pet)
    : pet_(std::move(pet)) {
  if (timeout && timeout->count() > 0) interval_ = *timeout / 2;
}

bool FrameWatchdog::frameCompleted(Clock::time_point now) {
  ++frames_;
  last_frame_ = now;
  if (!interval_) return false;
  if (last_pet_ && now - *last_pet_ < *interval_) return false;
  last_pet_ = now;
  ++pets_;
  if (pet_) pet_();
  return true;
}

double FrameWatchdog::secondsSinceProgress(Clock::time_point now) const {
  if (!last_frame_) return 0.0;
  return std::chrono::duration<double>(now - *last_frame_).count();
}

}  // namespace holo::kiosk
