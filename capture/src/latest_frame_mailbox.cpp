#include "holo/capture/latest_frame_mailbox.hpp"

#include "holo/core/stats.hpp"

namespace holo::capture {

void LatestFrameMailbox::publish(RgbdFrame frame) {
  static auto& dropped_total = stats::counter("Capture/Frames dropped (overwritten in mailbox)");
  bool dropped = false;
  {
    std::lock_guard lock(mutex_);
    ++counts_.published;
    if (slot_) {
      ++counts_.dropped;
      dropped = true;
    }
    latest_ = frame;
    slot_ = std::move(frame);
  }
  if (dropped) dropped_total.fetch_add(1, std::memory_order_relaxed);
  arrived_.notify_one();
}

std::optional<RgbdFrame> LatestFrameMailbox::take() {
  std::lock_guard lock(mutex_);
  std::optional<RgbdFrame> out;
  out.swap(slot_);
  if (out) ++counts_.taken;
  return out;
}

std::optional<RgbdFrame> LatestFrameMailbox::waitAndTake(Nanoseconds timeout) {
  std::unique_lock lock(mutex_);
  arrived_.wait_for(lock, timeout, [this] { return slot_.has_value(); });
  std::optional<RgbdFrame> out;
  out.swap(slot_);
  if (out) ++counts_.taken;
  return out;
}

std::optional<RgbdFrame> LatestFrameMailbox::peekLatest() const {
  std::lock_guard lock(mutex_);
  return latest_;
}

MailboxCounts LatestFrameMailbox::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

}  // namespace holo::capture
