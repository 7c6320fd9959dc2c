// Replaying a recording of two-device cameras (depth images with their own times, as
// `simulate --calibration` writes) pairs colour and depth like the live source: within the
// configuration's pair_tolerance_ms every frame pairs with its own depth image; beyond it every
// pair is dropped and counted, and the health counters say so.
#include <gtest/gtest.h>

#include <fstream>

#include "holo/capture/capture_config.hpp"
#include "holo/capture/recorder.hpp"
#include "holo/capture/recording_source.hpp"
#include "shared_data.hpp"

namespace holo::capture {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 6;

// 30 Hz colour, each depth image `skew_ms` after its colour image; frame k's depth reads (k + 1) m
// everywhere, so a pair shows whether its depth is its own.
fs::path writeSkewedRecording(const std::string& name, double skew_ms) {
  const fs::path dir = test::scratchDir(name) / "rec";
  Recorder recorder(dir, {{"cam0", "SN-0", std::nullopt}});
  for (int k = 0; k < kFrames; ++k) {
    RgbdFrame frame;
    frame.camera_id = 0;
    frame.colour = cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(10 * k));
    frame.depth = cv::Mat(6, 8, CV_32FC1, cv::Scalar(k + 1.0));
    frame.device_time = Nanoseconds(std::llround(k * 1e9 / 30.0));
    recorder.write(frame, frame.device_time + Nanoseconds(std::llround(skew_ms * 1e6)));
  }
  return dir;
}

struct Replay {
  std::vector<RgbdFrame> frames;
  CameraHealth health;
};

Replay replayAll(CameraSource& source) {
  Replay out;
  source.open();
  source.start();
  for (;;) {
    GrabResult result = source.grab(std::chrono::milliseconds(100));
    if (result.status == GrabStatus::EndOfStream) break;
    EXPECT_EQ(result.status, GrabStatus::Ok) << result.message;
    out.frames.push_back(std::move(result.frame));
  }
  out.health = source.health().snapshot();
  return out;
}

Nanoseconds ms(double t) {
  return Nanoseconds(std::llround(t * 1e6));
}

TEST(RecordingPairing, ASkewWithinTheToleranceKeepsEveryPair) {
  const Recording recording = readRecording(writeSkewedRecording("recording_pairing_kept", 15.0));
  ASSERT_NEAR(recording.cameras[0].frames[0].depth_timestamp_s - recording.cameras[0].frames[0].timestamp_s,
              0.015, 1e-6);
  RecordingSource source(recording.cameras[0], ReplayOptions{.pair_tolerance = ms(kDefaultPairToleranceMs)});
  const Replay replay = replayAll(source);
  ASSERT_EQ(replay.frames.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_FLOAT_EQ(replay.frames[k].depth.at<float>(0, 0), k + 1.0f)
        << "frame " << k << " got another's depth";
    // Recordings keep microseconds.
    EXPECT_EQ(replay.frames[k].device_time, Nanoseconds(1000 * std::llround(k * 1e6 / 30.0)));
  }
  EXPECT_EQ(replay.health.frames_unpaired, 0);
  EXPECT_NEAR(replay.health.pair_skew_ms, 15.0, 0.002);
}

TEST(RecordingPairing, ASkewBeyondTheToleranceDropsAndCountsEveryPair) {
  const Recording recording = readRecording(writeSkewedRecording("recording_pairing_dropped", 15.0));
  RecordingSource source(recording.cameras[0], ReplayOptions{.pair_tolerance = ms(5.0)});
  const Replay replay = replayAll(source);
  EXPECT_TRUE(replay.frames.empty());
  EXPECT_EQ(replay.health.frames_unpaired, 2 * kFrames);  // every colour and every depth image
  // Without a tolerance the recording's associations are replayed as they are.
  RecordingSource as_recorded(recording.cameras[0]);
  EXPECT_EQ(replayAll(as_recorded).frames.size(), static_cast<std::size_t>(kFrames));
}

// The configuration's capture.pair_tolerance_ms reaches a recording camera.
TEST(RecordingPairing, TheConfiguredToleranceAppliesToRecordings) {
  const fs::path rec = writeSkewedRecording("recording_pairing_config", 15.0);
  for (const auto& [tolerance_ms, frames] : {std::pair{5.0, 0}, std::pair{16.0, kFrames}}) {
    const fs::path yaml = rec.parent_path() / "installation.yaml";
    std::ofstream(yaml) << "capture:\n  pair_tolerance_ms: " << tolerance_ms
                        << "\n  cameras:\n    - {face: 0, backend: recording, path: rec}\n";
    const CaptureConfig config = loadCaptureConfig(yaml);
    const std::unique_ptr<CameraSource> source = makeSource(config.cameras.at(0));
    const Replay replay = replayAll(*source);
    EXPECT_EQ(replay.frames.size(), static_cast<std::size_t>(frames)) << tolerance_ms << " ms";
    EXPECT_EQ(replay.health.frames_unpaired, 2 * (kFrames - frames)) << tolerance_ms << " ms";
  }
}

}  // namespace
}  // namespace holo::capture
