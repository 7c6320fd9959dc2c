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

// Two live streams as a device delivers them: each pop returns the stream's next frame, or a
// timeout once it has none. Depth 15 ms behind colour, depth frame 2 lost in transit.
struct TwoStreams {
  std::vector<StampedImage> colour, depth;
  std::size_t next_colour = 0, next_depth = 0;
  int colour_pops = 0, depth_pops = 0;

  StreamPop pop(bool want_colour) {
    std::vector<StampedImage>& stream = want_colour ? colour : depth;
    std::size_t& next = want_colour ? next_colour : next_depth;
    ++(want_colour ? colour_pops : depth_pops);
    if (next >= stream.size()) return {GrabStatus::Timeout, {}, "nothing arrived"};
    return {GrabStatus::Ok, stream[next++], {}};
  }
};

TEST(FramePairing, GrabPairPopsEachStreamAsThePairerNeedsAndReportsDropsAndSkew) {
  TwoStreams streams;
  for (int k = 0; k < 4; ++k) {
    const double t = k * 1000.0 / 30.0;
    streams.colour.push_back(stamped(t, static_cast<float>(k)));
    if (k != 2) streams.depth.push_back(stamped(t + 15.0, static_cast<float>(k)));
  }
  FramePairer pairer(ms(kDefaultPairToleranceMs));
  HealthCounters health;
  const auto pop = [&](bool colour) { return streams.pop(colour); };

  std::vector<float> paired;
  for (int grab = 0; grab < 3; ++grab) {
    GrabResult g = grabPair(pairer, health, pop);
    ASSERT_EQ(g.status, GrabStatus::Ok) << "grab " << grab << ": " << g.message;
    EXPECT_EQ(g.frame.colour.at<float>(0, 0), g.frame.depth.at<float>(0, 0));
    // The colour side's device time travels with the frame.
    EXPECT_EQ(g.frame.device_time, ms(g.frame.colour.at<float>(0, 0) * 1000.0 / 30.0));
    EXPECT_NEAR(static_cast<double>(health.pair_skew_us.load()), 15000.0, 1.0);
    paired.push_back(g.frame.colour.at<float>(0, 0));
  }
  EXPECT_EQ(paired, (std::vector<float>{0.0f, 1.0f, 3.0f}));
  // Colour frame 2 had no depth frame within 16 ms (depth 3 came 48 ms after it): dropped, counted.
  EXPECT_EQ(health.frames_unpaired.load(), 1);
  // Every frame was popped once, none twice: the loop asks a stream only when the pairer needs it.
  EXPECT_EQ(streams.colour_pops, 4);
  EXPECT_EQ(streams.depth_pops, 3);

  // Both streams dry: the timeout comes back as such, with the stream's message.
  GrabResult none = grabPair(pairer, health, pop);
  EXPECT_EQ(none.status, GrabStatus::Timeout);
  EXPECT_EQ(none.message, "nothing arrived");
}

TEST(FramePairing, GrabPairKeepsWhatWasPoppedWhenAStreamFailsMidway) {
  TwoStreams streams;
  streams.colour.push_back(stamped(0.0, 7.0f));
  FramePairer pairer(ms(kDefaultPairToleranceMs));
  HealthCounters health;
  const auto pop = [&](bool colour) { return streams.pop(colour); };
  // The colour frame arrived, its depth frame not yet: a timeout, the colour frame kept.
  EXPECT_EQ(grabPair(pairer, health, pop).status, GrabStatus::Timeout);
  EXPECT_TRUE(pairer.hasColour());
  streams.depth.push_back(stamped(5.0, 7.0f));
  GrabResult g = grabPair(pairer, health, pop);
  ASSERT_EQ(g.status, GrabStatus::Ok);
  EXPECT_EQ(g.frame.colour.at<float>(0, 0), 7.0f);
  EXPECT_NEAR(static_cast<double>(health.pair_skew_us.load()), 5000.0, 1.0);
  EXPECT_EQ(health.frames_unpaired.load(), 0);
}

}  // namespace
}  // namespace holo::capture
