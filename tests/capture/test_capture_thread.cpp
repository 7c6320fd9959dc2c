#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "holo/capture/capture_thread.hpp"
#include "holo/core/error.hpp"

using namespace holo;
using namespace holo::capture;
using namespace std::chrono_literals;

namespace {

// A source that misbehaves on a schedule: its open() fails the first `failed_opens` times, and
// grab() throws every `throw_every`-th call and reports a disconnect every `disconnect_every`-th.
class FlakySource : public CameraSource {
 public:
  int failed_opens = 0;
  int throw_every = 0;
  int disconnect_every = 0;
  std::atomic<int> opens{0};
  std::atomic<int> grabs{0};

  std::string name() const override { return "flaky"; }
  std::string serial() const override { return "FLAKY-1"; }
  void open() override {
    if (opens++ < failed_opens) throw Error("flaky: not reachable yet");
  }
  void start() override {}
  void stop() override {}
  GrabResult grab(Nanoseconds) override {
    const int n = ++grabs;
    std::this_thread::sleep_for(1ms);
    if (throw_every && n % throw_every == 0) throw std::runtime_error("flaky: driver exploded");
    if (disconnect_every && n % disconnect_every == 0) return {GrabStatus::Disconnected, {}, "cable pulled"};
    GrabResult r;
    r.status = GrabStatus::Ok;
    r.frame.colour = cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3));
    r.frame.sequence = static_cast<std::uint64_t>(n);
    return r;
  }
};

template <class Pred>
bool waitFor(Pred pred, std::chrono::milliseconds limit = 30000ms) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(2ms);
  }
  return pred();
}

}  // namespace

TEST(CaptureThread, SurvivesASourceThatThrowsAndReconnects) {
  auto source = std::make_unique<FlakySource>();
  source->failed_opens = 2;
  source->throw_every = 7;
  FlakySource* raw = source.get();
  LatestFrameMailbox box;
  CaptureOptions options;
  options.camera_id = 3;
  options.initial_backoff = 5ms;
  options.max_backoff = 20ms;
  CaptureThread thread(std::move(source), box, options);
  ASSERT_TRUE(waitFor([&] { return thread.health().frames_completed >= 30; }));
  EXPECT_TRUE(thread.running());
  const CameraHealth h = thread.health();
  EXPECT_GE(h.disconnects, 3);  // every 7th grab threw, each one a disconnect
  EXPECT_GE(h.reconnects, 3);
  EXPECT_GE(h.frames_failed, 3);
  EXPECT_GE(raw->opens.load(), 2 + 1 + 3);  // two failed opens, the first success, reconnects
  EXPECT_GE(h.last_frame_age_s, 0.0);
  EXPECT_LT(h.last_frame_age_s, 1.0);
  const auto frame = box.take();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->camera_id, 3);
  EXPECT_NE(frame->host_time, Clock::time_point{});
  thread.stop();
  EXPECT_FALSE(thread.running());
  EXPECT_FALSE(thread.health().connected);
}

TEST(CaptureThread, DisconnectStatusCountsAndResumes) {
  auto source = std::make_unique<FlakySource>();
  source->disconnect_every = 5;
  LatestFrameMailbox box;
  CaptureOptions options;
  options.initial_backoff = 2ms;
  CaptureThread thread(std::move(source), box, options);
  ASSERT_TRUE(waitFor([&] { return thread.health().frames_completed >= 20; }));
  thread.stop();
  const CameraHealth h = thread.health();
  // Four frames per five grabs; each fifth a disconnect followed by a reconnect.
  EXPECT_GE(h.disconnects, 4);
  EXPECT_NEAR(static_cast<double>(h.disconnects), h.frames_completed / 4.0, 1.5);
  EXPECT_GE(h.reconnects, h.disconnects - 1);
}

TEST(CaptureThread, StopsPromptlyWhileBackingOff) {
  auto source = std::make_unique<FlakySource>();
  source->failed_opens = 1000;  // never reachable
  const FlakySource& flaky = *source;
  LatestFrameMailbox box;
  CaptureOptions options;
  // An hour of back-off: a stop that waited for it would take an hour, so 30 s proves the sleep
  // was interrupted on any machine, however busy.
  options.initial_backoff = std::chrono::hours(1);
  options.max_backoff = std::chrono::hours(1);
  CaptureThread thread(std::move(source), box, options);
  ASSERT_TRUE(waitFor([&] { return flaky.opens >= 1; }));
  const auto t0 = Clock::now();
  thread.stop();
  EXPECT_LT(Clock::now() - t0, 30s);
  EXPECT_EQ(thread.health().frames_completed, 0);
  EXPECT_EQ(box.counts().published, 0);
}
