#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "holo/capture/latest_frame_mailbox.hpp"

using namespace holo;
using namespace holo::capture;
using namespace std::chrono_literals;

namespace {
RgbdFrame frameNumber(std::uint64_t n) {
  RgbdFrame f;
  f.camera_id = 0;
  f.sequence = n;
  f.depth = cv::Mat(4, 4, CV_32FC1, cv::Scalar(static_cast<float>(n)));
  return f;
}
}  // namespace

TEST(LatestFrameMailbox, EmptyTakeReturnsNothingWithoutWaiting) {
  LatestFrameMailbox box;
  const auto start = Clock::now();
  EXPECT_FALSE(box.take().has_value());
  EXPECT_FALSE(box.peekLatest().has_value());
  EXPECT_LT(Clock::now() - start, 50ms);
}

TEST(LatestFrameMailbox, KeepsOnlyTheNewestAndCountsOverwrites) {
  LatestFrameMailbox box;
  for (std::uint64_t n = 0; n < 5; ++n) box.publish(frameNumber(n));
  const auto got = box.take();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->sequence, 4u);
  EXPECT_FALSE(box.take().has_value());  // taken means gone
  ASSERT_TRUE(box.peekLatest().has_value());
  EXPECT_EQ(box.peekLatest()->sequence, 4u);
  const MailboxCounts c = box.counts();
  EXPECT_EQ(c.published, 5);
  EXPECT_EQ(c.dropped, 4);
  EXPECT_EQ(c.taken, 1);
}

// A producer at full speed and a consumer that takes 20 ms per frame: the producer never waits
// for the consumer, the consumer always sees increasing sequence numbers, and
// published = taken + dropped (+ at most one frame left in the slot).
TEST(LatestFrameMailbox, SlowConsumerNeverBlocksTheProducer) {
  LatestFrameMailbox box;
  std::atomic<bool> stop{false};
  std::atomic<std::int64_t> produced{0};
  std::int64_t slowest_publish_us = 0;
  std::thread producer([&] {
    std::uint64_t n = 0;
    while (!stop) {
      const auto t0 = Clock::now();
      box.publish(frameNumber(n++));
      const auto us = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - t0).count();
      slowest_publish_us = std::max<std::int64_t>(slowest_publish_us, us);
      produced = static_cast<std::int64_t>(n);
      std::this_thread::sleep_for(1ms);
    }
  });
  std::uint64_t last = 0;
  int taken = 0;
  bool increasing = true;
  for (int i = 0; i < 10; ++i) {
    if (auto f = box.waitAndTake(200ms)) {
      if (taken > 0 && f->sequence <= last) increasing = false;
      last = f->sequence;
      ++taken;
      // Pixels are the producer's, untouched by later publishes.
      EXPECT_EQ(f->depth.at<float>(0, 0), static_cast<float>(f->sequence));
    }
    std::this_thread::sleep_for(20ms);  // the slow consumer
  }
  stop = true;
  producer.join();
  const MailboxCounts c = box.counts();
  EXPECT_TRUE(increasing);
  EXPECT_EQ(taken, 10);
  EXPECT_EQ(c.taken, 10);
  EXPECT_EQ(c.published, produced.load());
  // The producer made many more frames than the consumer took; the difference was dropped.
  EXPECT_GT(c.published, 5 * c.taken);
  EXPECT_GE(c.dropped, c.published - c.taken - 1);
  EXPECT_LE(c.dropped, c.published - c.taken);
  // No publish waited on the consumer's 20 ms of work (generous bound for a loaded CI machine).
  EXPECT_LT(slowest_publish_us, 15000);
}
