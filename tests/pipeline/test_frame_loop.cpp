// The live frame loop run in-process on the simulated museum: frames come out with the relic on
// them, the same inputs give the same images, and a camera whose stream ends leaves the
// foreground while the others go on. Small views (48 pixels) and a small panorama keep it quick.
// The overlapped foreground worker (the next frame's acquisition and foreground point cloud while
// this one renders) runs in every test here; CI runs them under ThreadSanitizer
// (docs/security.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/median.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::pipeline {
namespace {

constexpr int kViewSize = 48;
constexpr int kPanoramaWidth = 128;

FrameLoopOptions smallOptions() {
  FrameLoopOptions options;
  options.view_size = kViewSize;
  options.panorama_width = kPanoramaWidth;
  return options;
}

std::vector<cv::Mat> displayedViews(const FrameLoop& loop) {
  std::vector<cv::Mat> views;
  for (const reflect::ViewImages& view : loop.lastResult().views) views.push_back(view.display.clone());
  return views;
}

TEST(FrameLoop, RendersFramesOfTheSimulatedMuseumWithTheRelicOnThem) {
  FrameLoop loop(smallOptions(), simulated::installationFor(smallOptions()), nullptr);
  EXPECT_EQ(loop.cameras().size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const FrameReport report = loop.step();
    EXPECT_EQ(report.index, i);
    EXPECT_FALSE(report.cameras_ended);
    EXPECT_EQ(report.cameras_live, 4);
    EXPECT_EQ(report.non_finite_pixels, 0);
    EXPECT_GT(report.relic_pixels, 0u);
    EXPECT_GT(report.times.total, 0.0);
    // The loop thread's CPU is counted for the stages that do work on it. Not compared with the
    // process's clock: with a process CPU timer armed (a CPU-time limit, as CI sets) the kernel
    // updates that clock by ticks, so it can read less than the thread's own.
    EXPECT_GT(report.foreground_cpu.loop_thread_ms, 0.0);
    EXPECT_GT(report.rendering_cpu.loop_thread_ms, 0.0);
  }
  const std::vector<cv::Mat> views = displayedViews(loop);
  ASSERT_EQ(views.size(), 4u);
  for (const cv::Mat& view : views) {
    ASSERT_EQ(view.size(), cv::Size(kViewSize, kViewSize));
    ASSERT_EQ(view.type(), CV_8UC3);
    cv::Mat grey;
    cv::extractChannel(view, grey, 1);
    // The relic fills part of each view, lit; around it the view is black.
    const double lit = double(cv::countNonZero(grey > 8)) / double(grey.total());
    EXPECT_GT(lit, 0.05);
    EXPECT_LT(lit, 0.95);
  }
  const CameraFrameCounts counts = loop.cameraFrameCounts();
  EXPECT_TRUE(counts.simulated);  // during the run: no preloading
  EXPECT_EQ(counts.consumed, 4 * 3);
}

TEST(FrameLoop, RelearnsTheBackgroundFromTheNextFramesAndKeepsCameraImagesOnlyWhenAsked) {
  FrameLoop loop(smallOptions(), simulated::installationFor(smallOptions()), nullptr);
  std::size_t visitors = 0;
  for (int i = 0; i < 3; ++i) visitors = loop.step().foreground_points;
  EXPECT_GT(visitors, 0u);  // the simulated museum has visitors in view
  EXPECT_TRUE(loop.cameraColour().empty());
  loop.relearnBackground();
  // The worker's frame in flight was made before the relearn; the frames after it are learnt
  // from, so they have no foreground.
  loop.step();
  loop.keepCameraImages(true);
  const FrameReport learning = loop.step();
  EXPECT_EQ(learning.foreground_points, 0u);
  EXPECT_GT(learning.relic_pixels, 0u);  // the relic is shown meanwhile
  ASSERT_EQ(loop.cameraColour().size(), 4u);
  for (const cv::Mat& image : loop.cameraColour()) {
    EXPECT_EQ(image.type(), CV_8UC3);
    EXPECT_FALSE(image.empty());
  }
}

TEST(FrameLoop, TheSameInputsGiveTheSameImages) {
  std::vector<std::vector<cv::Mat>> runs;
  for (int run = 0; run < 2; ++run) {
    FrameLoop loop(smallOptions(), simulated::installationFor(smallOptions()), nullptr);
    loop.step();
    loop.step();
    runs.push_back(displayedViews(loop));
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (std::size_t v = 0; v < runs[0].size(); ++v)
    EXPECT_EQ(cv::norm(runs[0][v], runs[1][v], cv::NORM_L1), 0.0) << "view " << v;
}

TEST(FrameLoop, ACameraWhoseStreamEndsIsDroppedAndTheOthersGoOn) {
  const FrameLoopOptions options = smallOptions();
  Installation installation =
      simulated::museumInstallation(options.scene, /*paced=*/false, options.panorama_width);
  // Camera 3 delivers two frames, then reports the end of its stream, as a recording that ended.
  auto museum = std::make_shared<const sim::Museum>(sim::loadScene(options.scene));
  installation.sources[3] = std::make_unique<simulated::SimulatedSource>(
      museum, 3, simulated::SimulationOptions{.paced = false, .frame_count = 2});
  FrameLoop loop(options, std::move(installation), nullptr);
  std::vector<int> live;
  for (int i = 0; i < 4; ++i) {
    const FrameReport report = loop.step();
    ASSERT_FALSE(report.cameras_ended);  // the other three go on
    EXPECT_GT(report.relic_pixels, 0u);
    live.push_back(report.cameras_live);
  }
  EXPECT_EQ(live, (std::vector<int>{4, 4, 3, 3}));
}

// Overlap on and off see the same frames in the same order (deterministic mode), so they give the
// same images: the worker changes when the foreground runs, never what it computes.
TEST(FrameLoop, OverlappedForegroundGivesTheSameImagesAsSequential) {
  std::vector<std::vector<cv::Mat>> runs;
  for (const bool overlap : {true, false}) {
    FrameLoopOptions options = smallOptions();
    options.overlap = overlap;
    FrameLoop loop(options, simulated::installationFor(options), nullptr);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(loop.step().cameras_live, 4);
    runs.push_back(displayedViews(loop));
  }
  ASSERT_EQ(runs[0].size(), 4u);
  ASSERT_EQ(runs[1].size(), 4u);
  for (std::size_t v = 0; v < runs[0].size(); ++v)
    EXPECT_EQ(cv::norm(runs[0][v], runs[1][v], cv::NORM_L1), 0.0) << "view " << v;
}

// Live mode with the overlap: four capture threads publish into their mailboxes while the worker
// takes their frames and runs the foreground and the loop's thread renders the frame before and
// reads the mailboxes' counters. A camera stays in the foreground however slowly the simulation
// delivers (no staleness), so once each has published, every frame has all four.
TEST(FrameLoop, LiveCamerasFeedTheOverlappedForegroundWhileFramesRender) {
  FrameLoopOptions options = smallOptions();
  options.live = true;
  options.overlap = true;
  options.stale_camera_s = 1e6;
  FrameLoop loop(options, simulated::installationFor(options), nullptr);
  int frames_with_all = 0;
  std::int64_t dropped = 0;
  for (int i = 0; i < 2000 && frames_with_all < 4; ++i) {
    const FrameReport report = loop.step();
    ASSERT_FALSE(report.cameras_ended);
    EXPECT_EQ(report.non_finite_pixels, 0);
    EXPECT_GT(report.relic_pixels, 0u);
    EXPECT_GE(report.dropped_frames, 0);
    dropped += report.dropped_frames;
    if (report.cameras_live == 4) {
      ++frames_with_all;
      EXPECT_GT(report.foreground_points, 0u);  // the museum's visitors
    }
    // The frame carries when each camera frame it shows arrived. Each arrived before the frame's
    // foreground step took it, so the whole rendering after that separates it from the
    // presentation: a stamp taken anywhere else (the step's start, the worker's end) would fail.
    // (Stamps of one clock in their causal order; the pass times are sums over views rendered in
    // parallel, no bound on a wall interval.)
    ASSERT_EQ(report.camera_arrivals.size(), 4u);
    int arrived = 0;
    for (const auto& arrival : report.camera_arrivals)
      if (arrival) {
        ++arrived;
        EXPECT_LE(*arrival, report.acquired_at);
      }
    EXPECT_EQ(arrived, report.cameras_live);
    if (arrived > 0) {
      EXPECT_LE(report.acquired_at, report.rendering_started_at);
      EXPECT_LE(report.rendering_started_at, report.rendering_done_at);
      EXPECT_LE(report.rendering_done_at, report.presented_at);
    }
  }
  EXPECT_EQ(frames_with_all, 4);
  loop.waitForWorker();
  const CameraFrameCounts counts = loop.cameraFrameCounts();
  EXPECT_TRUE(counts.live);
  EXPECT_GE(counts.consumed, 4);  // each camera's frames were taken at least once
  // Every frame published was taken, overwritten, or is still waiting: at most one per mailbox.
  EXPECT_GE(counts.unconsumed - counts.dropped, 0);
  EXPECT_LE(counts.unconsumed - counts.dropped, 4);
  EXPECT_GE(counts.dropped, dropped);  // the steps' drops plus those since the last step
  EXPECT_EQ(counts.rejected, 0);
}

// When a camera's frames had surely reached its mailbox: its capture thread publishes frame k
// before it asks for frame k + 1, so frame k is there once grab() is entered for the next one.
struct PublishLog {
  std::mutex mutex;
  std::vector<Clock::time_point> grab_entered;  // call j returns frame j
  // Frames newer than `sequence` that had reached the mailbox before `t`.
  int newerPublishedBefore(std::uint64_t sequence, Clock::time_point t) {
    std::lock_guard lock(mutex);
    int newer = 0;
    for (std::size_t k = static_cast<std::size_t>(sequence) + 1; k + 1 < grab_entered.size(); ++k)
      if (grab_entered[k + 1] < t) ++newer;
    return newer;
  }
};

// A camera that costs nothing to produce: the same frame, numbered from 0, one every
// kCameraPeriod, much faster than the loop renders, so newer frames keep arriving while it works.
class NumberedCamera final : public capture::CameraSource {
 public:
  static constexpr std::chrono::milliseconds kCameraPeriod{2};
  NumberedCamera(RgbdFrame frame, std::shared_ptr<PublishLog> log,
                 std::chrono::milliseconds period = kCameraPeriod)
      : frame_(std::move(frame)), log_(std::move(log)), period_(period) {}
  std::string name() const override { return "numbered"; }
  std::string serial() const override { return "NUMBERED"; }
  void open() override {}
  void start() override {}
  void stop() override {}
  capture::GrabResult grab(Nanoseconds) override {
    {
      std::lock_guard lock(log_->mutex);
      log_->grab_entered.push_back(Clock::now());
    }
    std::this_thread::sleep_for(period_);
    capture::GrabResult result;
    result.status = capture::GrabStatus::Ok;
    result.frame = frame_;  // frames are values: the pixels are shared, never written
    result.frame.sequence = next_++;
    result.frame.host_time = Clock::now();
    return result;
  }

 private:
  RgbdFrame frame_;
  std::shared_ptr<PublishLog> log_;
  std::chrono::milliseconds period_;
  std::uint64_t next_ = 0;
};

// The simulated museum's installation with every camera replaced by a NumberedCamera of `period`
// showing the empty hall with a box 1 m in front of it (a visitor for the foreground).
Installation numberedCameraInstallation(const FrameLoopOptions& options, std::chrono::milliseconds period,
                                        std::vector<std::shared_ptr<PublishLog>>& logs) {
  Installation installation =
      simulated::museumInstallation(options.scene, /*paced=*/true, options.panorama_width);
  for (std::size_t i = 0; i < installation.sources.size(); ++i) {
    RgbdFrame frame = installation.background[i];
    frame.colour = frame.colour.clone();
    frame.depth = frame.depth.clone();
    const cv::Rect box(frame.colour.cols / 3, frame.colour.rows / 4, frame.colour.cols / 3,
                       frame.colour.rows / 2);
    frame.colour(box).setTo(cv::Scalar(40, 60, 200));
    frame.depth(box).setTo(cv::Scalar(1.0f));
    logs.push_back(std::make_shared<PublishLog>());
    installation.sources[i] = std::make_unique<NumberedCamera>(frame, logs.back(), period);
  }
  return installation;
}

// Live, a frame's camera frames are the newest ones when its foreground step takes them, and that
// step takes them only once the frame before has been rendered: counted in camera frames, none
// that had arrived before the previous frame's rendering ended is newer than the one shown. Taken
// when the previous frame started rendering (its foreground computed beside that rendering), every
// frame would show camera frames a whole rendering older than those at hand, and this fails.
TEST(FrameLoop, LiveFramesTakeTheNewestCameraFramesOnceThePreviousFrameIsRendered) {
  FrameLoopOptions options = smallOptions();
  options.live = true;
  options.overlap = true;
  options.stale_camera_s = 1e6;
  std::vector<std::shared_ptr<PublishLog>> logs;
  Installation installation = numberedCameraInstallation(options, NumberedCamera::kCameraPeriod, logs);
  constexpr int kFrames = 6;
  std::vector<FrameReport> reports;
  {
    FrameLoop loop(options, std::move(installation), nullptr);
    for (int n = 0; n < kFrames; ++n) reports.push_back(loop.step());
  }  // the capture threads have stopped: the logs are complete

  int shown = 0, newer_during_rendering = 0;
  for (std::size_t n = 0; n < reports.size(); ++n) {
    const FrameReport& report = reports[n];
    ASSERT_EQ(report.camera_sequences.size(), logs.size());
    EXPECT_LE(report.acquired_at, report.foreground_done_at);
    EXPECT_LE(report.foreground_done_at, report.rendering_started_at);
    EXPECT_LE(report.rendering_started_at, report.rendering_done_at);
    EXPECT_LE(report.rendering_done_at, report.presented_at);
    for (std::size_t i = 0; i < logs.size(); ++i) {
      const std::optional<std::uint64_t> sequence = report.camera_sequences[i];
      if (!sequence) continue;
      ++shown;
      EXPECT_EQ(logs[i]->newerPublishedBefore(*sequence, report.acquired_at), 0)
          << "frame " << n << " camera " << i << ": not the newest when its foreground step took it";
      if (n > 0) {
        EXPECT_EQ(logs[i]->newerPublishedBefore(*sequence, reports[n - 1].rendering_done_at), 0)
            << "frame " << n << " camera " << i << ": taken before the previous frame was rendered";
      }
      // The check has teeth: the cameras kept delivering while the frame was made.
      newer_during_rendering += logs[i]->newerPublishedBefore(*sequence, report.presented_at);
    }
  }
  EXPECT_GE(shown, 4 * (kFrames - 1));
  EXPECT_GT(newer_during_rendering, 0);
}

struct FreshFrames {
  int new_frames = 0;  // camera frames shown that the frame before had not shown
  int compared = 0;
  double median_frame_ms = 0;
};

FreshFrames runWithCamerasOf(std::chrono::milliseconds period, double fresh_frame_wait_ms) {
  FrameLoopOptions options = smallOptions();
  options.live = true;
  options.stale_camera_s = 1e6;
  options.fresh_frame_wait_ms = fresh_frame_wait_ms;
  std::vector<std::shared_ptr<PublishLog>> logs;
  Installation installation = numberedCameraInstallation(options, period, logs);
  // Compared from the frame after every camera's third frame was shown (the arrivals' period is
  // known from the second), over ten frames.
  constexpr std::uint64_t kFirstComparedSequence = 3;
  constexpr int kComparedFrames = 10;
  std::vector<FrameReport> reports;
  std::size_t first_compared = 0;
  {
    FrameLoop loop(options, std::move(installation), nullptr);
    const auto seenEnough = [&](const FrameReport& report) {
      return std::all_of(
          report.camera_sequences.begin(), report.camera_sequences.end(),
          [&](const auto& sequence) { return sequence && *sequence >= kFirstComparedSequence; });
    };
    while (first_compared == 0 && reports.size() < 1000) {
      reports.push_back(loop.step());
      if (seenEnough(reports.back())) first_compared = reports.size();
    }
    for (int n = 0; n < kComparedFrames; ++n) reports.push_back(loop.step());
  }
  FreshFrames out;
  std::vector<double> frame_ms;
  for (std::size_t n = std::max<std::size_t>(first_compared, 1); n < reports.size(); ++n) {
    frame_ms.push_back(reports[n].times.total);
    for (std::size_t i = 0; i < logs.size(); ++i) {
      const auto& now = reports[n].camera_sequences[i];
      const auto& before = reports[n - 1].camera_sequences[i];
      if (!now || !before) continue;
      ++out.compared;
      if (*now > *before) ++out.new_frames;
    }
  }
  out.median_frame_ms = median(frame_ms);
  return out;
}

// Live, the foreground step waits for a camera frame predicted to arrive within
// fresh_frame_wait_ms instead of showing the one it has: with cameras four times slower than the
// window, nearly every frame shows camera frames the frame before had not. Without the wait a loop
// faster than its cameras shows the same camera frames again in most frames (checked where this
// machine runs the loop in under half a camera period: on a loaded one it may not).
TEST(FrameLoop, LiveFramesWaitForCameraFramesAboutToArrive) {
  constexpr std::chrono::milliseconds kSlowCameras{100};
  const FreshFrames waiting = runWithCamerasOf(kSlowCameras, 400.0);
  ASSERT_GT(waiting.compared, 0);
  EXPECT_GE(waiting.new_frames, waiting.compared * 3 / 4)
      << waiting.new_frames << " of " << waiting.compared << " camera frames new with the wait";
  const FreshFrames not_waiting = runWithCamerasOf(kSlowCameras, 0.0);
  ASSERT_GT(not_waiting.compared, 0);
  if (not_waiting.median_frame_ms < 0.5 * static_cast<double>(kSlowCameras.count())) {
    EXPECT_LE(not_waiting.new_frames, not_waiting.compared * 3 / 4)
        << not_waiting.new_frames << " of " << not_waiting.compared << " camera frames new without the wait";
  }
}

TEST(FrameLoop, RefusesANegativeFreshFrameWait) {
  FrameLoopOptions options = smallOptions();
  options.fresh_frame_wait_ms = -1.0;
  try {
    FrameLoop loop(options, simulated::installationFor(options), nullptr);
    FAIL() << "a negative wait was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fresh_frame_wait_ms"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::pipeline
