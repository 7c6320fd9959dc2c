// Replays one camera of a recording (any layout readRecording() knows) as a CameraSource.
// Frames keep their recorded timestamps as device_time. Paced replay sleeps so frames come at
// their recorded intervals (scaled by `speed`); unpaced replay is as fast as files load.
//
// A recording of two-device cameras stores each depth image's own time (associations.txt). With
// a pair tolerance the replay pairs colour and depth by those times as a live two-device camera
// does (frame_pairing.hpp): a colour frame without a depth frame within the tolerance is dropped,
// and so is every depth frame passed over; the health counters hold the drops (frames_unpaired)
// and the last pair's skew (pair_skew_ms), as the live source's do.
#pragma once

#include <cstddef>
#include <optional>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/frame_pairing.hpp"
#include "holo/capture/recording.hpp"

namespace holo::capture {

struct ReplayOptions {
  bool paced = false;
  double speed = 1.0;  // > 0; 2 = twice as fast as recorded
  bool loop = false;   // start again after the last frame instead of EndOfStream
  // Pair colour and depth by their recorded times within this (capture.pair_tolerance_ms);
  // nullopt: the recording's associations as they are.
  std::optional<Nanoseconds> pair_tolerance;
};

class RecordingSource : public CameraSource {
 public:
  RecordingSource(RecordedCamera camera, ReplayOptions options = {});

  std::string name() const override { return "recording:" + camera_.name; }
  std::string serial() const override { return camera_.serial; }
  void open() override;
  void start() override;
  void stop() override {}
  GrabResult grab(Nanoseconds timeout) override;
  std::optional<CameraModel> cameraModel() const override { return camera_.model; }
  // The recording stores PNG units per metre (recording.hpp, the TUM convention).
  double metresPerDepthUnit() const override { return 1.0 / camera_.depth_scale; }

  std::size_t frameCount() const { return camera_.frames.size(); }
  // Loads frame `index` directly (tests, `info`); throws InputError for an unreadable file.
  RgbdFrame load(std::size_t index) const;

 private:
  // Sleeps until frame `index` is due (paced replay); false when it is not due within `timeout`.
  bool waitUntilDue(std::size_t index, Nanoseconds timeout);
  cv::Mat loadColour(const RecordedFrame& f) const;
  cv::Mat loadDepth(const RecordedFrame& f) const;
  GrabResult grabPaired(Nanoseconds timeout);

  RecordedCamera camera_;
  ReplayOptions options_;
  std::optional<FramePairer> pairer_;
  std::size_t next_ = 0;
  std::uint64_t sequence_ = 0;
  Clock::time_point replay_start_;
  double first_timestamp_ = 0;
};

}  // namespace holo::capture
