// KioskLoop in-process, with frame callbacks that behave like a frame loop would: a slow first
// frame, cameras that drop out and return, a frame source that throws.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "holo/kiosk/kiosk_loop.hpp"

namespace holo::kiosk {
namespace {

using namespace std::chrono_literals;

LoadedConfig testConfig() {
  LoadedConfig c{ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"), {}, "test", {}};
  c.kiosk = parseKioskConfig(c.root);
  c.kiosk.max_fps = 240;
  c.kiosk.health_port = -1;
  c.kiosk.health_file.clear();
  c.kiosk.degradation.down_after_frames = 3;
  c.kiosk.degradation.recover_after_frames = 5;
  return c;
}

std::vector<CameraHealth> cameras(int alive) {
  std::vector<CameraHealth> c(4);
  for (int i = 0; i < 4; ++i) {
    c[static_cast<std::size_t>(i)].name = "cam" + std::to_string(i);
    c[static_cast<std::size_t>(i)].alive = i < alive;
  }
  return c;
}

bool hasError(const HealthStatus& h, const std::string& text) {
  for (const auto& e : h.last_errors)
    if (e.find(text) != std::string::npos) return true;
  return false;
}

TEST(KioskLoop, ASlowFirstFrameDoesNotLowerTheQuality) {
  // A budget far above what the trivial frames take on a loaded machine, still well under the
  // slow first frame: the test does not depend on the machine's speed.
  const auto config = [] {
    LoadedConfig c = testConfig();
    c.kiosk.degradation.frame_budget_ms = 150.0;
    return c;
  };
  SignalEvents signals;
  SystemdNotifier notifier;
  std::vector<int> qualities;
  KioskLoop loop(
      config(),
      [&](const FrameRequest& r) {
        qualities.push_back(r.quality);
        if (r.index == 0) std::this_thread::sleep_for(300ms);  // shader compilation, caches
        FrameReport report;
        report.presented = true;
        report.cameras = cameras(4);
        return report;
      },
      config);
  EXPECT_EQ(loop.run(signals, notifier, 30), 0);
  ASSERT_EQ(qualities.size(), 30u);
  EXPECT_EQ(qualities.back(), 0);
  EXPECT_EQ(loop.health().quality, "full");
  EXPECT_EQ(loop.health().frames, 30);
}

TEST(KioskLoop, CameraLossAndRecoveryReachTheRequestAndTheHealth) {
  SignalEvents signals;
  SystemdNotifier notifier;
  std::vector<RenderMode> modes;
  KioskLoop loop(
      testConfig(),
      [&](const FrameRequest& r) {
        modes.push_back(r.mode);
        FrameReport report;
        report.presented = true;
        // Frames 10..19: two cameras lost; 20..29: none; from 30 all back.
        report.cameras = cameras(r.index < 10 ? 4 : r.index < 20 ? 2 : r.index < 30 ? 0 : 4);
        return report;
      },
      [] { return testConfig(); });
  EXPECT_EQ(loop.run(signals, notifier, 45), 0);
  // The mode is decided after a frame, so it reaches the next request.
  EXPECT_EQ(modes[9], RenderMode::Full);
  EXPECT_EQ(modes[11], RenderMode::Partial);
  EXPECT_EQ(modes[21], RenderMode::IblOnly);
  EXPECT_EQ(modes[33], RenderMode::IblOnly);  // recovery waits recover_after_frames (5)
  EXPECT_EQ(modes[36], RenderMode::Full);
  const HealthStatus h = loop.health();
  EXPECT_EQ(h.mode, "full");
  EXPECT_TRUE(hasError(h, "mode 'partial' with cameras 2/4"));
  EXPECT_TRUE(hasError(h, "mode 'ibl-only' with cameras 0/4"));
  EXPECT_EQ(h.cameras.size(), 4u);
}

TEST(KioskLoop, ASecondCameraLostAFrameAfterTheFirstIsReportedThoughTheModeStaysPartial) {
  // Two cameras switched off together are seen lost a frame apart when their last frames were.
  SignalEvents signals;
  SystemdNotifier notifier;
  KioskLoop loop(
      testConfig(),
      [&](const FrameRequest& r) {
        FrameReport report;
        report.presented = true;
        report.cameras = cameras(r.index < 10 ? 4 : r.index < 11 ? 3 : r.index < 20 ? 2 : 3);
        return report;
      },
      [] { return testConfig(); });
  EXPECT_EQ(loop.run(signals, notifier, 30), 0);
  const HealthStatus h = loop.health();
  EXPECT_EQ(h.mode, "partial");
  EXPECT_TRUE(hasError(h, "mode 'partial' with cameras 3/4"));
  EXPECT_TRUE(hasError(h, "mode 'partial' with cameras 2/4"));
  // A camera coming back is its own event ("camera N back"), not a mode line.
  EXPECT_EQ(std::count_if(h.last_errors.begin(), h.last_errors.end(),
                          [](const std::string& e) { return e.rfind("mode '", 0) == 0; }),
            2);
}

TEST(KioskLoop, AThrowingFrameSourceIsReportedNotFatalAndNotRepeatedInTheLog) {
  SignalEvents signals;
  SystemdNotifier notifier;
  KioskLoop loop(
      testConfig(),
      [&](const FrameRequest& r) -> FrameReport {
        if (r.index >= 5 && r.index < 25) throw std::runtime_error("GPU lost");
        FrameReport report;
        report.presented = true;
        return report;
      },
      [] { return testConfig(); });
  EXPECT_EQ(loop.run(signals, notifier, 30), 0);
  const HealthStatus h = loop.health();
  EXPECT_EQ(h.frames, 10);  // only the presented ones count
  int reports = 0;
  for (const auto& e : h.last_errors) reports += e == "frame failed: GPU lost" ? 1 : 0;
  EXPECT_EQ(reports, 1);
}

TEST(KioskLoop, AFailedFrameKeepsTheCameraModeItCannotKnow) {
  // A render error is no camera fault: with all cameras delivering, failing frames must neither
  // switch to ibl-only nor report lost cameras.
  SignalEvents signals;
  SystemdNotifier notifier;
  std::vector<RenderMode> modes;
  KioskLoop loop(
      testConfig(),
      [&](const FrameRequest& r) -> FrameReport {
        modes.push_back(r.mode);
        if (r.index % 4 == 3) throw std::runtime_error("render error");
        FrameReport report;
        report.presented = true;
        report.cameras = cameras(4);
        return report;
      },
      [] { return testConfig(); });
  EXPECT_EQ(loop.run(signals, notifier, 30), 0);
  EXPECT_EQ(std::count(modes.begin(), modes.end(), RenderMode::Full), 30);
  const HealthStatus h = loop.health();
  EXPECT_EQ(h.camerasAlive(), 4);
  EXPECT_FALSE(hasError(h, "mode '"));
  EXPECT_TRUE(hasError(h, "frame failed: render error"));
}

}  // namespace
}  // namespace holo::kiosk
