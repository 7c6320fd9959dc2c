// When a camera's next frame will reach the host, predicted from the frames taken so far, and how
// long the live foreground step waits for frames about to arrive (docs/frame_loop.md, "Waiting
// for a camera frame about to arrive").
//
// A camera delivers at its own rate (30 fps for the simulated and the fitted ones); the loop takes
// each camera's newest frame whenever its foreground step starts, so a frame shown is on average
// half a camera period old when taken. Where a camera's next frame is due within a short window,
// waiting for it shows a frame that much newer for a frame time that much longer: the predictor
// says when it is due, freshFrameDeadline whether and how long to wait.
//
// Units: the steady clock's time points; periods in seconds. Threads: one predictor per camera,
// used by one thread at a time (the loop's worker).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "holo/core/rgbd_frame.hpp"  // Clock

namespace holo::pipeline {

class ArrivalPredictor {
 public:
  // A frame taken from the camera: its source's frame number and when it reached the host. The
  // period is the median of the last few (arrival difference / frame number difference) between
  // successive observed frames, so frames the loop never took (dropped in the mailbox) count as
  // elapsed periods; a number that goes back or jumps (a restarted source) starts afresh.
  void observe(std::uint64_t sequence, Clock::time_point arrival);
  // The next frame's predicted arrival (the last one plus the period); none until two frames a
  // few numbers apart have been seen.
  std::optional<Clock::time_point> nextArrival() const;
  std::optional<double> periodSeconds() const;

 private:
  static constexpr std::size_t kPeriodsKept = 9;
  static constexpr std::uint64_t kLargestStep = 8;  // frame numbers between two observations
  std::optional<std::uint64_t> last_sequence_;
  Clock::time_point last_arrival_{};
  std::deque<double> periods_s_;
};

// Whether a predicted arrival falls within (now, now + window]: a frame about to arrive, not one
// already late.
bool dueWithin(const std::optional<Clock::time_point>& arrival, Clock::time_point now,
               Clock::duration window);

// The moment the foreground step waits until for frames about to arrive: the latest of the
// predicted arrivals that fall within (now, now + window], plus `slack` for a frame's jitter;
// none when no camera's next frame is due within the window (or the window is 0).
std::optional<Clock::time_point> freshFrameDeadline(
    const std::vector<std::optional<Clock::time_point>>& arrivals, Clock::time_point now,
    Clock::duration window, Clock::duration slack);

}  // namespace holo::pipeline
