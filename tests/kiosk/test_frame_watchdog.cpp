#include <gtest/gtest.h>
#include <vector>

#include "holo/kiosk/frame_watchdog.hpp"

namespace holo::kiosk {
namespace {

using namespace std::chrono_literals;
using Clock = FrameWatchdog::Clock;

TEST(FrameWatchdog, PetsAtHalfTheTimeoutWhileFramesFlow) {
  int pets = 0;
  FrameWatchdog w(std::chrono::microseconds(1'000'000), [&] { ++pets; });
  ASSERT_TRUE(w.petInterval());
  EXPECT_EQ(*w.petInterval(), 500ms);
  const Clock::time_point t0{};
  // 25 fps for 3 s: a pet on the first frame at least 0.5 s after the previous pet, so at 0,
  // 0.52, 1.04, 1.56, 2.08 and 2.6 s (never once per frame, never later than a frame late).
  std::vector<Clock::time_point> times;
  for (int i = 0; i <= 75; ++i)
    if (w.frameCompleted(t0 + i * 40ms)) times.push_back(t0 + i * 40ms);
  EXPECT_EQ(pets, 6);
  EXPECT_EQ(w.pets(), 6);
  for (std::size_t i = 1; i < times.size(); ++i) {
    EXPECT_GE(times[i] - times[i - 1], 500ms);
    EXPECT_LT(times[i] - times[i - 1], 540ms);
  }
  EXPECT_EQ(w.frames(), 76);
}

TEST(FrameWatchdog, AHungFrameStopsThePets) {
  int pets = 0;
  FrameWatchdog w(std::chrono::microseconds(1'000'000), [&] { ++pets; });
  const Clock::time_point t0{};
  w.frameCompleted(t0);
  EXPECT_EQ(pets, 1);
  // No frames for 10 s: nothing calls the watchdog, so nothing is sent, and the stall shows.
  EXPECT_DOUBLE_EQ(w.secondsSinceProgress(t0 + 10s), 10.0);
  EXPECT_EQ(pets, 1);
  // The first frame after the hang pets at once.
  EXPECT_TRUE(w.frameCompleted(t0 + 10s));
  EXPECT_EQ(pets, 2);
}

TEST(FrameWatchdog, OffWithoutTimeoutButStillTracksProgress) {
  int pets = 0;
  FrameWatchdog w(std::nullopt, [&] { ++pets; });
  const Clock::time_point t0{};
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(w.frameCompleted(t0 + i * 1s));
  EXPECT_EQ(pets, 0);
  EXPECT_EQ(w.frames(), 10);
  EXPECT_DOUBLE_EQ(w.secondsSinceProgress(t0 + 11s), 2.0);
}

}  // namespace
}  // namespace holo::kiosk
