// Pairing colour and depth frames that come from two devices: each stream's frames carry the time
// they reached the host (one clock for both devices; their own clocks differ unless synchronised
// by PTP). A colour frame is paired with the depth frame nearest in time when the two are at most
// `tolerance` apart; a colour frame with no depth frame that near is dropped, and so is every
// depth frame passed over - both counted. The pairing of a colour frame is decided as soon as a
// depth frame at or after it arrived (a later one can only be further away), so a pair waits at
// most for the next depth frame. Each stream must arrive in time order.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "holo/capture/camera_source.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::capture {

// Default for capture.pair_tolerance_ms: half a frame at 30 Hz, so a colour frame never pairs
// with a depth frame nearer to the next colour frame.
inline constexpr double kDefaultPairToleranceMs = 16.0;

struct StampedImage {
  cv::Mat image;
  Nanoseconds time{0};         // host arrival time
  Nanoseconds device_time{0};  // the device's own timestamp (kept on the pair's colour side)
};

struct FramePair {
  StampedImage colour;
  StampedImage depth;
  double skew_ms = 0.0;  // depth time - colour time
};

class FramePairer {
 public:
  explicit FramePairer(Nanoseconds tolerance);

  void pushColour(StampedImage frame);
  void pushDepth(StampedImage frame);
  // The oldest colour frame whose pairing is decided: its pair, or nothing (then it was dropped,
  // and the next one is looked at). nullopt when no decided pair is waiting. `streams_ended`: no
  // frame will follow (a recording's end), so every colour frame is decided against the depth
  // frames there are, and depth frames left after the last colour frame are dropped.
  std::optional<FramePair> pop(bool streams_ended = false);
  // True when the oldest colour frame waits for a depth frame at or after it.
  bool waitingForDepth() const;
  bool hasColour() const { return !colour_.empty(); }
  void clear();

  std::int64_t droppedColour() const { return dropped_colour_; }
  std::int64_t droppedDepth() const { return dropped_depth_; }
  std::int64_t paired() const { return paired_; }

 private:
  Nanoseconds tolerance_;
  std::deque<StampedImage> colour_;
  std::deque<StampedImage> depth_;
  std::int64_t dropped_colour_ = 0;
  std::int64_t dropped_depth_ = 0;
  std::int64_t paired_ = 0;
};

// One frame popped from one stream of a two-device camera, or why there is none.
struct StreamPop {
  GrabStatus status = GrabStatus::Timeout;
  StampedImage frame;  // status Ok only
  std::string message;
};

// The oldest decided pair as a frame: the colour image, the depth image at its own size (the loop
// registers it) and the colour side's device time; the drops (frames_unpaired) and the pair's
// skew go to `health`. nullopt while no decided pair waits. Sequence and host time are the
// source's to set.
std::optional<RgbdFrame> popPairedFrame(FramePairer& pairer, HealthCounters& health,
                                        bool streams_ended = false);

// Feeds `pairer` from a camera's two live streams until it decides a pair, returned as by
// popPairedFrame: `pop(true)` pops a colour frame while none waits in the pairer, `pop(false)` a
// depth frame otherwise (each pop waits as long as the device's timeout). A pop that fails ends
// the call with its status and message; frames popped before stay in the pairer for the next call.
GrabResult grabPair(FramePairer& pairer, HealthCounters& health,
                    const std::function<StreamPop(bool colour)>& pop);

}  // namespace holo::capture
