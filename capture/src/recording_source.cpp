#include "holo/capture/recording_source.hpp"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "holo/core/error.hpp"

namespace holo::capture {

RecordingSource::RecordingSource(RecordedCamera camera, ReplayOptions options)
    : camera_(std::move(camera)), options_(options) {
  if (!(options_.speed > 0))
    throw InputError("", "replay speed", "a positive factor", std::to_string(options_.speed));
}

void RecordingSource::open() {
  if (camera_.frames.empty()) throw InputError(camera_.name, "frames", "at least one recorded frame", "none");
}

void RecordingSource::start() {
  next_ = 0;
  replay_start_ = Clock::now();
  first_timestamp_ = camera_.frames.front().timestamp_s;
}

RgbdFrame RecordingSource::load(std::size_t index) const {
  const RecordedFrame& f = camera_.frames.at(index);
  RgbdFrame frame;
  for (const auto& file : {f.colour, f.depth})
    if (!file.empty() && !std::filesystem::exists(file))
      throw InputError(file.string(), "", "an image listed in the recording's index", "missing");
  if (!f.colour.empty()) {
    frame.colour = cv::imread(f.colour.string(), cv::IMREAD_COLOR);
    if (frame.colour.empty())
      throw InputError(f.colour.string(), "", "a readable colour image", "cannot decode");
  }
  if (!f.depth.empty()) {
    const cv::Mat raw = cv::imread(f.depth.string(), cv::IMREAD_ANYDEPTH);
    if (raw.empty()) throw InputError(f.depth.string(), "", "a readable depth image", "cannot decode");
    if (raw.type() != CV_16UC1)
      throw InputError(f.depth.string(), "", "a 16-bit single-channel depth PNG", "another pixel type");
    frame.depth = depthFromU16(raw, camera_.depth_scale);
  }
  if (!frame.colour.empty() && !frame.depth.empty() && frame.colour.size() != frame.depth.size())
    throw InputError(f.depth.string(), "size", "the size of its colour image " + f.colour.filename().string(),
                     std::to_string(frame.depth.cols) + "x" + std::to_string(frame.depth.rows));
  frame.camera_id = camera_.id;
  frame.device_time = Nanoseconds(std::llround(f.timestamp_s * 1e9));
  return frame;
}

GrabResult RecordingSource::grab(Nanoseconds timeout) {
  if (next_ >= camera_.frames.size()) {
    if (!options_.loop) return {GrabStatus::EndOfStream, {}, "end of recording"};
    start();
  }
  if (options_.paced) {
    const auto offset = std::chrono::duration<double>((camera_.frames[next_].timestamp_s - first_timestamp_) /
                                                      options_.speed);
    const auto due = replay_start_ + std::chrono::duration_cast<Clock::duration>(offset);
    const auto now = Clock::now();
    if (due - now > timeout) {
      std::this_thread::sleep_for(timeout);
      return {GrabStatus::Timeout, {}, "next recorded frame not due yet"};
    }
    std::this_thread::sleep_until(due);
  }
  const std::size_t index = next_++;
  GrabResult result;
  try {
    result.frame = load(index);
  } catch (const InputError& e) {
    // A damaged file loses one frame, not the replay.
    return {GrabStatus::Failed, {}, e.what()};
  }
  result.status = GrabStatus::Ok;
  result.frame.sequence = sequence_++;
  result.frame.host_time = Clock::now();
  return result;
}

}  // namespace holo::capture
