#include "camera_acquisition.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "holo/core/log.hpp"
#include "holo/core/stopwatch.hpp"

namespace holo::pipeline {

CameraAcquisition::CameraAcquisition(Installation& installation, bool live, double stale_camera_s,
                                     Clock::duration fresh_frame_wait)
    : live_(live),
      stale_camera_s_(stale_camera_s),
      fresh_frame_wait_(fresh_frame_wait),
      cameras_(installation.cameras),
      capture_options_(installation.capture_options),
      depth_correction_(installation.depth_correction),
      depth_to_colour_(installation.depth_to_colour) {
  const std::size_t n = cameras_.size();
  rejected_.assign(n, std::string());
  if (live_) {
    latest_.resize(n);
    arrivals_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      mailboxes_.push_back(std::make_unique<capture::LatestFrameMailbox>());
      threads_.push_back(std::make_unique<capture::CaptureThread>(std::move(installation.sources[i]),
                                                                  *mailboxes_.back(), capture_options_[i]));
    }
  } else {
    sources_ = std::move(installation.sources);
    source_ended_.assign(n, 0);
    for (auto& source : sources_) {
      source->open();
      source->start();
    }
  }
  installation.sources.clear();
}

CameraAcquisition::~CameraAcquisition() {
  for (auto& thread : threads_) thread->stop();
  if (next_frames_.valid()) next_frames_.wait();
  for (auto& source : sources_) source->stop();
}

RgbdFrame CameraAcquisition::grabFrom(std::size_t camera) {
  if (source_ended_[camera]) return {};
  capture::CameraSource& source = *sources_[camera];
  const capture::CaptureOptions& options = capture_options_[camera];
  const auto give_up = Clock::now() + options.silence_timeout;
  for (;;) {
    capture::GrabResult result = source.grab(options.grab_timeout);
    switch (result.status) {
      case capture::GrabStatus::Ok:
        result.frame.camera_id = static_cast<int>(camera);
        return std::move(result.frame);
      case capture::GrabStatus::EndOfStream:
        HOLO_LOG_INFO("camera {}: end of stream", source.name());
        source_ended_[camera] = 1;
        return {};
      case capture::GrabStatus::Disconnected:
        HOLO_LOG_WARN("camera {}: disconnected ({}); missing this frame", source.name(), result.message);
        return {};
      default:
        if (Clock::now() > give_up) {
          HOLO_LOG_WARN("camera {}: no frame within {} ms ({}); missing this frame", source.name(),
                        options.silence_timeout.count(), result.message);
          return {};
        }
    }
  }
}

CameraAcquisition::Grabbed CameraAcquisition::grabDeterministic() {
  Grabbed out;
  out.frames.resize(sources_.size());
  tbb::parallel_for(std::size_t(0), sources_.size(), [&](std::size_t i) { out.frames[i] = grabFrom(i); });
  out.ended = std::all_of(source_ended_.begin(), source_ended_.end(), [](std::uint8_t e) { return e != 0; });
  return out;
}

std::vector<RgbdFrame> CameraAcquisition::waitLive() {
  std::vector<RgbdFrame> frames(mailboxes_.size());
  for (std::size_t i = 0; i < mailboxes_.size(); ++i)
    if (!threads_[i]->finished())
      if (auto fresh = mailboxes_[i]->waitAndTake(capture_options_[i].silence_timeout))
        frames[i] = std::move(*fresh);
  return frames;
}

void CameraAcquisition::takeNewestLive() {
  for (std::size_t i = 0; i < latest_.size(); ++i)
    if (auto fresh = mailboxes_[i]->take()) {
      latest_[i] = std::move(*fresh);
      arrivals_[i].observe(latest_[i].sequence, latest_[i].host_time);
    }
}

void CameraAcquisition::waitForFramesAboutToArrive() {
  // A frame's arrival stamp jitters with the capture thread's scheduling by about a millisecond.
  constexpr Clock::duration kSlack = std::chrono::milliseconds(2);
  if (fresh_frame_wait_ <= Clock::duration::zero()) return;
  std::vector<std::optional<Clock::time_point>> due(latest_.size());
  for (std::size_t i = 0; i < latest_.size(); ++i)
    if (!threads_[i]->finished()) due[i] = arrivals_[i].nextArrival();
  const auto now = Clock::now();
  const std::optional<Clock::time_point> deadline = freshFrameDeadline(due, now, fresh_frame_wait_, kSlack);
  if (!deadline) return;
  for (std::size_t i = 0; i < latest_.size(); ++i) {
    if (!dueWithin(due[i], now, fresh_frame_wait_)) continue;
    const auto left = std::max(Clock::duration::zero(), *deadline - Clock::now());
    if (auto fresh = mailboxes_[i]->waitAndTake(std::chrono::duration_cast<Nanoseconds>(left))) {
      latest_[i] = std::move(*fresh);
      arrivals_[i].observe(latest_[i].sequence, latest_[i].host_time);
    }
  }
}

CameraAcquisition::Grabbed CameraAcquisition::takeLive() {
  takeNewestLive();
  waitForFramesAboutToArrive();
  const auto now = Clock::now();
  takeNewestLive();  // what arrived while it waited
  Grabbed out;
  out.taken_at = now;
  out.frames.resize(latest_.size());
  out.ended = true;
  for (std::size_t i = 0; i < latest_.size(); ++i) {
    const bool stale = latest_[i].colour.empty() ||
                       std::chrono::duration<double>(now - latest_[i].host_time).count() > stale_camera_s_;
    if (!stale) out.frames[i] = latest_[i];  // an empty frame tells the pipeline the camera is missing
    out.ended = out.ended && threads_[i]->finished() && !mailboxes_[i]->peekLatest();
  }
  return out;
}

CameraAcquisition::Frames CameraAcquisition::next() {
  const auto t0 = Clock::now();
  Grabbed grabbed;
  if (live_) {
    grabbed = takeLive();
  } else if (!preloaded_.empty()) {
    grabbed = std::move(preloaded_.front());
    preloaded_.pop_front();
  } else {
    // Each frame's grab was started when the previous one was taken (the first one is grabbed now).
    grabbed = next_frames_.valid() ? next_frames_.get() : grabDeterministic();
    next_frames_ = std::async(std::launch::async, [this] { return grabDeterministic(); });
  }
  Frames out;
  out.wait_ms = msSince(t0);
  out.taken_at = live_ ? grabbed.taken_at : t0;
  out.frames = std::move(grabbed.frames);
  out.ended = grabbed.ended;
  correctDepth(out.frames);
  rejectUnusable(out.frames);
  return out;
}

std::vector<RgbdFrame> CameraAcquisition::backgroundFrame() {
  std::vector<RgbdFrame> frames = live_ ? waitLive() : grabDeterministic().frames;
  correctDepth(frames);
  rejectUnusable(frames);
  return frames;
}

void CameraAcquisition::preload(int frames) {
  if (live_) return;
  for (int f = 0; f < frames; ++f) preloaded_.push_back(grabDeterministic());
}

void CameraAcquisition::correctDepth(std::vector<RgbdFrame>& frames) const {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    RgbdFrame& frame = frames[i];
    if (frame.depth.empty() || frame.depth.type() != CV_32FC1) continue;  // rejectUnusable says why
    // Into new buffers: the frame's depth may be shared (the live mailbox, preloaded frames).
    if (i < depth_correction_.size() && depth_correction_[i] != 1.0f) {
      cv::Mat corrected;
      frame.depth.convertTo(corrected, CV_32FC1, depth_correction_[i]);
      frame.depth = corrected;
    }
    if (i < depth_to_colour_.size() && depth_to_colour_[i] &&
        frame.depth.size() == depth_to_colour_[i]->depthSize())
      frame.depth = depth_to_colour_[i]->apply(frame.depth);
  }
}

void CameraAcquisition::rejectUnusable(std::vector<RgbdFrame>& frames) {
  for (std::size_t i = 0; i < frames.size() && i < cameras_.size(); ++i) {
    RgbdFrame& frame = frames[i];
    if (frame.colour.empty() && frame.depth.empty()) continue;  // missing, nothing to say
    const cv::Size size(cameras_[i].width(), cameras_[i].height());
    std::string problem;
    if (frame.colour.type() != CV_8UC3 || frame.colour.size() != size)
      problem = fmt::format("colour {}x{} type {} (expected {}x{} 8-bit BGR)", frame.colour.cols,
                            frame.colour.rows, frame.colour.type(), size.width, size.height);
    else if (frame.depth.type() != CV_32FC1 || frame.depth.size() != size)
      problem = fmt::format("depth {}x{} type {} (expected {}x{} float metres, as calibrated)",
                            frame.depth.cols, frame.depth.rows, frame.depth.type(), size.width, size.height);
    if (problem.empty()) continue;
    // Once per camera and kind of problem: a camera that keeps sending such frames is missing.
    if (rejected_[i] != problem)
      HOLO_LOG_WARN("camera {}: frame not usable, treated as missing: {}", i, problem);
    rejected_[i] = problem;
    ++rejected_frames_;
    frame = RgbdFrame{};
  }
}

std::vector<capture::CameraHealth> CameraAcquisition::cameraHealth(std::int64_t frames_rendered) const {
  std::vector<capture::CameraHealth> health;
  for (const auto& thread : threads_) health.push_back(thread->health());
  if (threads_.empty())  // deterministic: the simulated cameras always deliver
    for (std::size_t i = 0; i < cameras_.size(); ++i) {
      capture::CameraHealth h;
      h.connected = true;
      h.frames_completed = frames_rendered;
      h.last_frame_age_s = 0.0;
      health.push_back(h);
    }
  return health;
}

CameraFrameCounts CameraAcquisition::counts(std::int64_t frames_rendered) const {
  CameraFrameCounts counts;
  counts.live = live_;
  counts.rejected = rejected_frames_.load();
  if (!live_) {
    counts.produced = counts.consumed = frames_rendered * static_cast<std::int64_t>(cameras_.size());
    return counts;
  }
  for (const auto& mailbox : mailboxes_) {
    const capture::MailboxCounts c = mailbox->counts();
    counts.produced += c.published;
    counts.consumed += c.taken;
    counts.dropped += c.dropped;
  }
  counts.unconsumed = counts.produced - counts.consumed;
  return counts;
}

}  // namespace holo::pipeline
