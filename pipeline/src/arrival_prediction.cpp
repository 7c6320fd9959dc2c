#include "arrival_prediction.hpp"

#include <chrono>

#include "holo/core/median.hpp"

namespace holo::pipeline {

void ArrivalPredictor::observe(std::uint64_t sequence, Clock::time_point arrival) {
  if (last_sequence_ && sequence == *last_sequence_) return;  // the frame seen before
  const bool follows = last_sequence_ && sequence > *last_sequence_ &&
                       sequence - *last_sequence_ <= kLargestStep && arrival > last_arrival_;
  if (follows) {
    const double elapsed_s = std::chrono::duration<double>(arrival - last_arrival_).count();
    periods_s_.push_back(elapsed_s / static_cast<double>(sequence - *last_sequence_));
    if (periods_s_.size() > kPeriodsKept) periods_s_.pop_front();
  } else if (last_sequence_) {
    periods_s_.clear();  // a restarted or renumbered source: its old rate says nothing
  }
  last_sequence_ = sequence;
  last_arrival_ = arrival;
}

std::optional<double> ArrivalPredictor::periodSeconds() const {
  if (periods_s_.empty()) return std::nullopt;
  return median(std::vector<double>(periods_s_.begin(), periods_s_.end()));
}

std::optional<Clock::time_point> ArrivalPredictor::nextArrival() const {
  const std::optional<double> period = periodSeconds();
  if (!period) return std::nullopt;
  return last_arrival_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(*period));
}

bool dueWithin(const std::optional<Clock::time_point>& arrival, Clock::time_point now,
               Clock::duration window) {
  return arrival && *arrival > now && *arrival - now <= window;
}

std::optional<Clock::time_point> freshFrameDeadline(
    const std::vector<std::optional<Clock::time_point>>& arrivals, Clock::time_point now,
    Clock::duration window, Clock::duration slack) {
  std::optional<Clock::time_point> latest;
  for (const std::optional<Clock::time_point>& arrival : arrivals)
    if (dueWithin(arrival, now, window) && (!latest || *arrival > *latest)) latest = arrival;
  if (!latest) return std::nullopt;
  return *latest + slack;
}

}  // namespace holo::pipeline
