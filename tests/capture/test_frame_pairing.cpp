// Colour and depth from two devices paired by arrival time: a depth stream 15 ms behind pairs
// every frame within the default tolerance; a lost depth frame drops its colour frame (counted)
// instead of pairing it with a frame 48 ms away; a skew beyond the tolerance pairs nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "holo/capture/frame_pairing.hpp"

namespace holo::capture {
namespace {

Nanoseconds ms(double t) {
  return Nanoseconds(static_cast<std::int64_t>(std::llround(t * 1e6)));
}

StampedImage stamped(double t_ms, float value) {
  return {cv::Mat(1, 1, CV_32FC1, cv::Scalar(value)), ms(t_ms), ms(t_ms)};
}

// 30 Hz colour from t = 0, depth `skew_ms` later, depth frames listed in `lost` never arrive.
// Frames are pushed in arrival order and pairs taken as soon as they are decided.
std::vector<FramePair> run(FramePairer& pairer, double skew_ms, const std::vector<int>& lost,
                           int frames = 30) {
  std::vector<FramePair> pairs;
  for (int k = 0; k < frames; ++k) {
    const double t = k * 1000.0 / 30.0;
    pairer.pushColour(stamped(t, static_cast<float>(k)));
    if (std::find(lost.begin(), lost.end(), k) == lost.end())
      pairer.pushDepth(stamped(t + skew_ms, static_cast<float>(k)));
    while (auto pair = pairer.pop()) pairs.push_back(std::move(*pair));
  }
  return pairs;
}

TEST(FramePairing, A15MillisecondSkewPairsEveryFrameWithinTheDefaultTolerance) {
  FramePairer pairer(ms(kDefaultPairToleranceMs));
  const std::vector<FramePair> pairs = run(pairer, 15.0, {});
  ASSERT_EQ(pairs.size(), 30u);
  for (const FramePair& p : pairs) {
    EXPECT_EQ(p.colour.image.at<float>(0), p.depth.image.at<float>(0));  // the same instant's frames
    EXPECT_NEAR(p.skew_ms, 15.0, 1e-6);
  }
  EXPECT_EQ(pairer.droppedColour(), 0);
  EXPECT_EQ(pairer.droppedDepth(), 0);
}

TEST(FramePairing, ALostDepthFrameDropsItsColourFrameInsteadOfMispairingIt) {
  FramePairer pairer(ms(kDefaultPairToleranceMs));
  const std::vector<FramePair> pairs = run(pairer, 15.0, {7, 20});
  ASSERT_EQ(pairs.size(), 28u);
  for (const FramePair& p : pairs) EXPECT_EQ(p.colour.image.at<float>(0), p.depth.image.at<float>(0));
  EXPECT_EQ(pairer.droppedColour(), 2);
  EXPECT_EQ(pairer.droppedDepth(), 0);
  // Depth arriving early (before its colour frame) pairs too; the last colour frame waits for a
  // depth frame after it to be sure no nearer one comes.
  FramePairer early(ms(kDefaultPairToleranceMs));
  const std::vector<FramePair> early_pairs = run(early, -10.0, {});
  ASSERT_EQ(early_pairs.size(), 29u);
  EXPECT_NEAR(early_pairs.front().skew_ms, -10.0, 1e-6);
  EXPECT_TRUE(early.waitingForDepth());
  // At the streams' end the waiting colour frame pairs with the depth frame before it.
  const std::optional<FramePair> last = early.pop(/*streams_ended=*/true);
  ASSERT_TRUE(last.has_value());
  EXPECT_NEAR(last->skew_ms, -10.0, 1e-6);
  EXPECT_FALSE(early.hasColour());
}

TEST(FramePairing, ASkewBeyondTheToleranceIsDroppedAndCounted) {
  FramePairer pairer(ms(10.0));
  const std::vector<FramePair> pairs = run(pairer, 15.0, {});
  EXPECT_TRUE(pairs.empty());
  EXPECT_EQ(pairer.droppedColour(), 30);
  EXPECT_EQ(pairer.droppedDepth(), 29);  // each passed over; the last may still pair
  // At the streams' end (a recording's last frame) nothing more can come: the last depth frame goes.
  EXPECT_FALSE(pairer.pop(/*streams_ended=*/true));
  EXPECT_EQ(pairer.droppedDepth(), 30);
}

}  // namespace
}  // namespace holo::capture
