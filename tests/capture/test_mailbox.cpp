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

// Nothing will ever be published here, so a take or peek that waited would never return.
TEST(LatestFrameMailbox, EmptyTakeReturnsNothingWithoutWaiting) {
  LatestFrameMailbox box;
  EXPECT_FALSE(box.take().has_value());
  EXPECT_FALSE(box.peekLatest().has_value());
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

// A producer at full speed and a consumer that keeps each frame until five more have been
// published: were a publish to wait for the consumer, that would never happen. The consumer always
// sees increasing sequence numbers, and published = taken + dropped (+ at most one frame left in
// the slot).
TEST(LatestFrameMailbox, SlowConsumerNeverBlocksTheProducer) {
  LatestFrameMailbox box;
  std::atomic<bool> stop{false};
  std::atomic<std::int64_t> produced{0};
  std::thread producer([&] {
    std::uint64_t n = 0;
    while (!stop) {
      box.publish(frameNumber(n++));
      produced = static_cast<std::int64_t>(n);
      std::this_thread::sleep_for(1ms);
    }
  });
  std::uint64_t last = 0;
  int taken = 0;
  bool increasing = true, producer_went_on = true;
  for (int i = 0; i < 10; ++i) {
    if (auto f = box.waitAndTake(30s)) {
      if (taken > 0 && f->sequence <= last) increasing = false;
      last = f->sequence;
      ++taken;
      // Pixels are the producer's, untouched by later publishes.
      EXPECT_EQ(f->depth.at<float>(0, 0), static_cast<float>(f->sequence));
      // The slow consumer: it holds the frame while the producer publishes five more.
      const auto wanted = static_cast<std::int64_t>(f->sequence) + 6;
      const auto give_up = Clock::now() + 30s;
      while (produced < wanted && Clock::now() < give_up) std::this_thread::sleep_for(1ms);
      producer_went_on = producer_went_on && produced >= wanted;
    }
  }
  stop = true;
  producer.join();
  const MailboxCounts c = box.counts();
  EXPECT_TRUE(increasing);
  EXPECT_TRUE(producer_went_on);
  EXPECT_EQ(taken, 10);
  EXPECT_EQ(c.taken, 10);
  EXPECT_EQ(c.published, produced.load());
  // The producer made many more frames than the consumer took; the difference was dropped.
  EXPECT_GT(c.published, 5 * c.taken);
  EXPECT_GE(c.dropped, c.published - c.taken - 1);
  EXPECT_LE(c.dropped, c.published - c.taken);
}
