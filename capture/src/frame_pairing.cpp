#include "holo/capture/frame_pairing.hpp"

#include <cmath>
#include <cstdlib>

namespace holo::capture {

FramePairer::FramePairer(Nanoseconds tolerance) : tolerance_(tolerance) {}

void FramePairer::pushColour(StampedImage frame) {
  colour_.push_back(std::move(frame));
}

void FramePairer::pushDepth(StampedImage frame) {
  depth_.push_back(std::move(frame));
}

bool FramePairer::waitingForDepth() const {
  return !colour_.empty() && (depth_.empty() || depth_.back().time < colour_.front().time);
}

void FramePairer::clear() {
  colour_.clear();
  depth_.clear();
}

std::optional<FramePair> FramePairer::pop(bool streams_ended) {
  while (!colour_.empty() && (streams_ended || !waitingForDepth())) {
    StampedImage colour = std::move(colour_.front());
    colour_.pop_front();
    // The nearest depth frame is the first at or after the colour's, or the one before it (at the
    // streams' end there may be no later one).
    std::size_t first_after = 0;
    while (first_after < depth_.size() && depth_[first_after].time < colour.time) ++first_after;
    std::size_t nearest = first_after;
    if (first_after > 0 && (first_after == depth_.size() || colour.time - depth_[first_after - 1].time <
                                                                depth_[first_after].time - colour.time))
      nearest = first_after - 1;
    const Nanoseconds gap = nearest < depth_.size() ? depth_[nearest].time - colour.time : Nanoseconds::max();
    if (nearest >= depth_.size() || std::llabs(gap.count()) > tolerance_.count()) {
      // Nothing near enough: the colour frame goes; the depth frames before it can match no later
      // colour frame either.
      ++dropped_colour_;
      dropped_depth_ += static_cast<std::int64_t>(first_after);
      depth_.erase(depth_.begin(), depth_.begin() + static_cast<std::ptrdiff_t>(first_after));
      continue;
    }
    FramePair pair;
    pair.colour = std::move(colour);
    pair.depth = std::move(depth_[nearest]);
    pair.skew_ms = static_cast<double>(gap.count()) * 1e-6;
    dropped_depth_ += static_cast<std::int64_t>(nearest);
    depth_.erase(depth_.begin(), depth_.begin() + static_cast<std::ptrdiff_t>(nearest) + 1);
    ++paired_;
    return pair;
  }
  if (streams_ended && colour_.empty()) {
    dropped_depth_ += static_cast<std::int64_t>(depth_.size());
    depth_.clear();
  }
  return std::nullopt;
}

std::optional<RgbdFrame> popPairedFrame(FramePairer& pairer, HealthCounters& health, bool streams_ended) {
  std::optional<FramePair> pair = pairer.pop(streams_ended);
  health.frames_unpaired.store(pairer.droppedColour() + pairer.droppedDepth(), std::memory_order_relaxed);
  if (!pair) return std::nullopt;
  health.pair_skew_us.store(static_cast<std::int64_t>(std::llround(pair->skew_ms * 1e3)),
                            std::memory_order_relaxed);
  RgbdFrame frame;
  frame.colour = std::move(pair->colour.image);
  frame.depth = std::move(pair->depth.image);
  frame.device_time = pair->colour.device_time;
  return frame;
}

GrabResult grabPair(FramePairer& pairer, HealthCounters& health,
                    const std::function<StreamPop(bool colour)>& pop) {
  for (;;) {
    if (std::optional<RgbdFrame> frame = popPairedFrame(pairer, health))
      return {GrabStatus::Ok, std::move(*frame), {}};
    const bool colour = !pairer.hasColour();
    StreamPop popped = pop(colour);
    if (popped.status != GrabStatus::Ok) return {popped.status, {}, std::move(popped.message)};
    if (colour)
      pairer.pushColour(std::move(popped.frame));
    else
      pairer.pushDepth(std::move(popped.frame));
  }
}

}  // namespace holo::capture
