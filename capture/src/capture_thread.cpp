#include "holo/capture/capture_thread.hpp"

#include <algorithm>

#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::capture {

CaptureThread::CaptureThread(std::unique_ptr<CameraSource> source, LatestFrameMailbox& mailbox,
                             CaptureOptions options)
    : source_(std::move(source)), mailbox_(mailbox), options_(options) {
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

CaptureThread::~CaptureThread() {
  stop();
}

void CaptureThread::stop() {
  {
    std::lock_guard lock(sleep_mutex_);
    stop_requested_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void CaptureThread::sleepInterruptibly(std::chrono::milliseconds duration) {
  std::unique_lock lock(sleep_mutex_);
  wake_.wait_for(lock, duration, [this] { return stop_requested_.load(); });
}

bool CaptureThread::connect() {
  try {
    source_->open();
    source_->start();
    return true;
  } catch (const std::exception& e) {
    HOLO_LOG_WARN("capture {}: cannot connect: {}", source_->name(), e.what());
    source_->stop();
    return false;
  }
}

void CaptureThread::disconnect(const std::string& why) {
  HOLO_LOG_WARN("capture {}: disconnected ({}); reconnecting", source_->name(), why);
  auto& h = source_->health();
  h.disconnects.fetch_add(1, std::memory_order_relaxed);
  h.connected = false;
  source_->stop();
}

void CaptureThread::run() {
  auto& h = source_->health();
  auto backoff = options_.initial_backoff;
  bool ever_connected = false;
  Clock::time_point silent_since{};  // start of the current run of timeouts
  while (!stop_requested_) {
    if (!h.connected) {
      if (!connect()) {
        sleepInterruptibly(backoff);
        backoff = std::min(backoff * 2, options_.max_backoff);
        continue;
      }
      if (ever_connected) h.reconnects.fetch_add(1, std::memory_order_relaxed);
      ever_connected = true;
      h.connected = true;
      backoff = options_.initial_backoff;
    }
    GrabResult result;
    try {
      result = source_->grab(options_.grab_timeout);
    } catch (const std::exception& e) {
      h.frames_failed.fetch_add(1, std::memory_order_relaxed);
      disconnect(std::string("grab threw: ") + e.what());
      continue;
    }
    switch (result.status) {
      case GrabStatus::Ok:
        result.frame.camera_id = options_.camera_id;
        if (result.frame.host_time == Clock::time_point{}) result.frame.host_time = Clock::now();
        h.markFrame(result.frame.host_time);
        mailbox_.publish(std::move(result.frame));
        silent_since = {};
        break;
      case GrabStatus::Timeout: {
        h.frames_timed_out.fetch_add(1, std::memory_order_relaxed);
        const auto now = Clock::now();
        if (silent_since == Clock::time_point{}) silent_since = now;
        if (now - silent_since >= options_.silence_timeout) {
          silent_since = {};
          disconnect("no frame for " + std::to_string(options_.silence_timeout.count()) + " ms");
        }
        break;
      }
      case GrabStatus::Incomplete:
        h.frames_incomplete.fetch_add(1, std::memory_order_relaxed);
        break;
      case GrabStatus::Failed:
        h.frames_failed.fetch_add(1, std::memory_order_relaxed);
        break;
      case GrabStatus::Disconnected:
        silent_since = {};
        disconnect(result.message);
        break;
      case GrabStatus::EndOfStream:
        if (options_.stop_at_end_of_stream) {
          finished_ = true;
          stop_requested_ = true;
        }
        break;
    }
  }
  source_->stop();
  h.connected = false;
  publishStats();
  running_ = false;
}

void CaptureThread::publishStats() const {
  const CameraHealth s = source_->health().snapshot();
  const std::string prefix = "Capture/" + source_->name() + ": ";
  stats::add(prefix + "frames completed", s.frames_completed);
  stats::add(prefix + "frames failed", s.frames_failed);
  stats::add(prefix + "frames timed out", s.frames_timed_out);
  stats::add(prefix + "frames incomplete", s.frames_incomplete);
  stats::add(prefix + "resends", s.resends);
  stats::add(prefix + "disconnects", s.disconnects);
  stats::add(prefix + "frames dropped in mailbox", mailbox_.counts().dropped);
}

}  // namespace holo::capture
