#include "replayed_source.hpp"

#include <thread>

#include "holo/core/error.hpp"

namespace holo::eval {

ReplayedSource::ReplayedSource(std::unique_ptr<capture::CameraSource> recorded, int frames, double fps)
    : recorded_name_(recorded->name()),
      serial_(recorded->serial()),
      model_(recorded->cameraModel()),
      metres_per_unit_(recorded->metresPerDepthUnit()),
      fps_(fps) {
  recorded->open();
  recorded->start();
  for (int k = 0; k < frames; ++k) {
    capture::GrabResult result = recorded->grab(std::chrono::seconds(10));
    if (result.status != capture::GrabStatus::Ok)
      throw Error("replayed camera " + recorded_name_ + ": frame " + std::to_string(k) + " of " +
                  std::to_string(frames) + " not recorded (" + capture::toString(result.status) + ": " +
                  result.message + ")");
    frames_.push_back(std::move(result.frame));
  }
  recorded->stop();
}

void ReplayedSource::start() {
  start_ = Clock::now();
  next_ = 0;
}

capture::GrabResult ReplayedSource::grab(Nanoseconds timeout) {
  const auto due = start_ + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>(static_cast<double>(next_) / fps_));
  if (due > Clock::now() + timeout) {
    std::this_thread::sleep_for(timeout);
    return {capture::GrabStatus::Timeout, {}, "next frame not due yet"};
  }
  std::this_thread::sleep_until(due);
  const RgbdFrame& recorded =
      frames_[static_cast<std::size_t>(next_ % static_cast<std::int64_t>(frames_.size()))];
  capture::GrabResult result;
  result.status = capture::GrabStatus::Ok;
  result.frame = recorded;  // frames are values: its pixels are shared, never written
  result.frame.sequence = static_cast<std::uint64_t>(next_);
  result.frame.device_time = std::chrono::duration_cast<Nanoseconds>(
      std::chrono::duration<double>(static_cast<double>(next_) / fps_));
  result.frame.host_time = Clock::now();
  ++next_;
  return result;
}

}  // namespace holo::eval
