// When a camera's next frame is due, from the frames the live loop took, and how long its
// foreground step waits for frames about to arrive (pipeline/src/arrival_prediction.hpp).
#include "arrival_prediction.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace holo::pipeline {
namespace {

using std::chrono::milliseconds;

const Clock::time_point kStart = Clock::time_point() + std::chrono::hours(1);

Clock::time_point at(double ms) {
  return kStart + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

double msAfterStart(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(t - kStart).count();
}

TEST(ArrivalPredictor, PredictsNothingFromOneFrame) {
  ArrivalPredictor predictor;
  EXPECT_FALSE(predictor.nextArrival());
  predictor.observe(7, at(0));
  EXPECT_FALSE(predictor.nextArrival());
  predictor.observe(7, at(5));  // the same frame seen again says nothing about the rate
  EXPECT_FALSE(predictor.nextArrival());
}

// A loop slower than its camera takes every second or third frame: the frames it never took count
// as periods elapsed, so the period is the camera's, not the loop's.
TEST(ArrivalPredictor, CountsTheFramesTheLoopNeverTookAsPeriods) {
  ArrivalPredictor predictor;
  const std::uint64_t taken[] = {10, 12, 13, 16, 18, 19, 22};
  for (std::uint64_t sequence : taken)
    predictor.observe(sequence, at(33.0 * static_cast<double>(sequence - 10)));
  ASSERT_TRUE(predictor.periodSeconds());
  EXPECT_NEAR(*predictor.periodSeconds(), 0.033, 1e-6);
  ASSERT_TRUE(predictor.nextArrival());
  EXPECT_NEAR(msAfterStart(*predictor.nextArrival()), 33.0 * 13, 1e-3);
}

// One late frame (the capture thread descheduled) does not move the median period.
TEST(ArrivalPredictor, OneLateArrivalDoesNotMoveThePeriod) {
  ArrivalPredictor predictor;
  for (std::uint64_t k = 0; k < 6; ++k) predictor.observe(k, at(33.0 * static_cast<double>(k)));
  predictor.observe(6, at(33.0 * 6 + 15.0));
  predictor.observe(7, at(33.0 * 7));
  EXPECT_NEAR(*predictor.periodSeconds(), 0.033, 1e-6);
}

// A source that starts its numbers again (reconnected, or a recording looping) is timed afresh.
TEST(ArrivalPredictor, ASourceThatRestartsItsNumbersIsTimedAfresh) {
  ArrivalPredictor predictor;
  for (std::uint64_t k = 100; k < 105; ++k) predictor.observe(k, at(20.0 * static_cast<double>(k - 100)));
  ASSERT_TRUE(predictor.nextArrival());
  predictor.observe(0, at(500));
  EXPECT_FALSE(predictor.nextArrival());
  predictor.observe(1, at(550));
  EXPECT_NEAR(*predictor.periodSeconds(), 0.050, 1e-6);
  predictor.observe(40, at(600));  // a jump of 39 frames: not a period
  EXPECT_FALSE(predictor.nextArrival());
}

TEST(FreshFrameDeadline, WaitsForTheLatestFrameDueWithinTheWindowPlusSlack) {
  const std::vector<std::optional<Clock::time_point>> arrivals = {at(104), std::nullopt, at(108), at(130)};
  const auto deadline = freshFrameDeadline(arrivals, at(100), milliseconds(10), milliseconds(2));
  ASSERT_TRUE(deadline);
  EXPECT_NEAR(msAfterStart(*deadline), 110.0, 1e-3);  // 108 + 2; 130 is beyond the window
}

TEST(FreshFrameDeadline, DoesNotWaitWhenNothingIsDueOrTheWindowIsZero) {
  // Due before now: the camera is late, and its frame may never come.
  EXPECT_FALSE(freshFrameDeadline({at(95), at(120)}, at(100), milliseconds(10), milliseconds(2)));
  EXPECT_FALSE(freshFrameDeadline({at(104)}, at(100), milliseconds(0), milliseconds(2)));
  EXPECT_FALSE(freshFrameDeadline({std::nullopt}, at(100), milliseconds(10), milliseconds(2)));
}

}  // namespace
}  // namespace holo::pipeline
