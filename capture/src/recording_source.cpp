#include "holo/capture/recording_source.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "holo/core/error.hpp"

namespace holo::capture {

RecordingSource::RecordingSource(RecordedCamera camera, ReplayOptions options)
    : camera_(std::move(camera)), options_(options) {
  if (!(options_.speed > 0))
    throw InputError("", "replay speed", "a positive factor", std::to_string(options_.speed));
  // Only frames with both images can be paired: a colour-only or depth-only camera replays as is.
  const bool rgbd = std::all_of(camera_.frames.begin(), camera_.frames.end(),
                                [](const RecordedFrame& f) { return !f.colour.empty() && !f.depth.empty(); });
  if (options_.pair_tolerance && rgbd) {
    if (options_.pair_tolerance->count() <= 0)
      throw InputError(camera_.name, "pair tolerance", "a positive time",
                       std::to_string(options_.pair_tolerance->count()) + " ns");
    pairer_.emplace(*options_.pair_tolerance);
  }
}

void RecordingSource::open() {
  if (camera_.frames.empty()) throw InputError(camera_.name, "frames", "at least one recorded frame", "none");
}

void RecordingSource::start() {
  next_ = 0;
  replay_start_ = Clock::now();
  first_timestamp_ = camera_.frames.front().timestamp_s;
  if (pairer_) pairer_->clear();
}

cv::Mat RecordingSource::loadColour(const RecordedFrame& f) const {
  if (f.colour.empty()) return {};
  if (!std::filesystem::exists(f.colour))
    throw InputError(f.colour.string(), "", "an image listed in the recording's index", "missing");
  cv::Mat colour = cv::imread(f.colour.string(), cv::IMREAD_COLOR);
  if (colour.empty()) throw InputError(f.colour.string(), "", "a readable colour image", "cannot decode");
  return colour;
}

cv::Mat RecordingSource::loadDepth(const RecordedFrame& f) const {
  if (f.depth.empty()) return {};
  if (!std::filesystem::exists(f.depth))
    throw InputError(f.depth.string(), "", "an image listed in the recording's index", "missing");
  const cv::Mat raw = cv::imread(f.depth.string(), cv::IMREAD_ANYDEPTH);
  if (raw.empty()) throw InputError(f.depth.string(), "", "a readable depth image", "cannot decode");
  if (raw.type() != CV_16UC1)
    throw InputError(f.depth.string(), "", "a 16-bit single-channel depth PNG", "another pixel type");
  return depthFromU16(raw, camera_.depth_scale);
}

RgbdFrame RecordingSource::load(std::size_t index) const {
  const RecordedFrame& f = camera_.frames.at(index);
  for (const auto& file : {f.colour, f.depth})
    if (!file.empty() && !std::filesystem::exists(file))
      throw InputError(file.string(), "", "an image listed in the recording's index", "missing");
  RgbdFrame frame;
  frame.colour = loadColour(f);
  frame.depth = loadDepth(f);
  if (!frame.colour.empty() && !frame.depth.empty() && frame.colour.size() != frame.depth.size())
    throw InputError(f.depth.string(), "size", "the size of its colour image " + f.colour.filename().string(),
                     std::to_string(frame.depth.cols) + "x" + std::to_string(frame.depth.rows));
  frame.camera_id = camera_.id;
  frame.device_time = Nanoseconds(std::llround(f.timestamp_s * 1e9));
  return frame;
}

bool RecordingSource::waitUntilDue(std::size_t index, Nanoseconds timeout) {
  if (!options_.paced) return true;
  const auto offset =
      std::chrono::duration<double>((camera_.frames[index].timestamp_s - first_timestamp_) / options_.speed);
  const auto due = replay_start_ + std::chrono::duration_cast<Clock::duration>(offset);
  if (due - Clock::now() > timeout) {
    std::this_thread::sleep_for(timeout);
    return false;
  }
  std::this_thread::sleep_until(due);
  return true;
}

// Colour and depth enter the pairer as two streams, each in its recorded time order; a pair
// leaves it once a depth frame at or after its colour frame has been read (or the recording ends).
GrabResult RecordingSource::grabPaired(Nanoseconds timeout) {
  for (;;) {
    const bool ended = next_ >= camera_.frames.size();
    if (std::optional<RgbdFrame> frame = popPairedFrame(*pairer_, health(), ended)) {
      GrabResult result{GrabStatus::Ok, std::move(*frame), {}};
      result.frame.camera_id = camera_.id;
      result.frame.sequence = sequence_++;
      result.frame.host_time = Clock::now();
      return result;
    }
    if (ended) {
      if (!options_.loop) return {GrabStatus::EndOfStream, {}, "end of recording"};
      start();
      continue;
    }
    if (!waitUntilDue(next_, timeout)) return {GrabStatus::Timeout, {}, "next recorded frame not due yet"};
    const RecordedFrame& f = camera_.frames[next_++];
    StampedImage colour, depth;
    try {
      colour.image = loadColour(f);
      depth.image = loadDepth(f);
    } catch (const InputError& e) {
      return {GrabStatus::Failed, {}, e.what()};  // a damaged file loses one frame, not the replay
    }
    colour.time = colour.device_time = Nanoseconds(std::llround(f.timestamp_s * 1e9));
    depth.time = depth.device_time = Nanoseconds(std::llround(f.depth_timestamp_s * 1e9));
    if (!colour.image.empty()) pairer_->pushColour(std::move(colour));
    if (!depth.image.empty()) pairer_->pushDepth(std::move(depth));
  }
}

GrabResult RecordingSource::grab(Nanoseconds timeout) {
  if (pairer_) return grabPaired(timeout);
  if (next_ >= camera_.frames.size()) {
    if (!options_.loop) return {GrabStatus::EndOfStream, {}, "end of recording"};
    start();
  }
  if (!waitUntilDue(next_, timeout)) return {GrabStatus::Timeout, {}, "next recorded frame not due yet"};
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
