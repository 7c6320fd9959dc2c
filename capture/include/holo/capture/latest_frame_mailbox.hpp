// A single-slot mailbox between one capture thread (producer) and the frame loop (consumer).
// The producer overwrites whatever is in the slot; the consumer takes the newest frame or
// nothing. Neither side ever waits for the other: the lock guards only a move of a frame header
// (cv::Mat shares pixels), never I/O or conversion. A frame that is overwritten before anyone
// took it counts as dropped.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "holo/core/rgbd_frame.hpp"

namespace holo::capture {

struct MailboxCounts {
  std::int64_t published = 0;  // frames put in by the producer
  std::int64_t taken = 0;      // frames handed to the consumer
  std::int64_t dropped = 0;    // frames overwritten before anyone took them
};

class LatestFrameMailbox {
 public:
  // Puts the newest frame in the slot, replacing (and counting as dropped) an untaken one.
  void publish(RgbdFrame frame);
  // The newest frame, if one arrived since the last take(); never waits.
  std::optional<RgbdFrame> take();
  // Like take(), but waits up to `timeout` for a frame (for consumers that want to, e.g. tests
  // and the recorder); the producer is never slowed down by a waiting consumer.
  std::optional<RgbdFrame> waitAndTake(Nanoseconds timeout);
  // The last frame ever published (also after it was taken), without consuming it.
  std::optional<RgbdFrame> peekLatest() const;

  MailboxCounts counts() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::optional<RgbdFrame> slot_;    // untaken newest frame
  std::optional<RgbdFrame> latest_;  // newest frame, taken or not
  MailboxCounts counts_;
};

}  // namespace holo::capture
