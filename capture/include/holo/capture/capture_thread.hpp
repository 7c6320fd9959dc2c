// One thread per camera: opens its source, grabs frames and publishes each complete one into the
// camera's LatestFrameMailbox. It never dies with its source: an exception or a Disconnected
// grab stops the source and reconnects with exponential back-off (initial_backoff doubling up to
// max_backoff), so a camera that is unplugged and plugged back resumes by itself. A run of
// timeouts longer than `silence_timeout` also counts as a disconnect (a GigE camera that lost
// power just goes quiet).
//
// Health: the source's HealthCounters are updated here and mirrored into holo::stats as
// "Capture/<name>: frames completed" etc. when the thread stops (stats are cheap totals; read
// health() for live values).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/latest_frame_mailbox.hpp"

namespace holo::capture {

struct CaptureOptions {
  int camera_id = 0;  // written into every published frame
  std::chrono::milliseconds grab_timeout{200};
  std::chrono::milliseconds initial_backoff{100};
  std::chrono::milliseconds max_backoff{5000};
  std::chrono::milliseconds silence_timeout{2000};  // timeouts in a row this long = disconnect
  bool stop_at_end_of_stream = true;                // a finished recording ends the thread
};

class CaptureThread {
 public:
  CaptureThread(std::unique_ptr<CameraSource> source, LatestFrameMailbox& mailbox,
                CaptureOptions options = {});
  ~CaptureThread();  // stop()
  CaptureThread(const CaptureThread&) = delete;
  CaptureThread& operator=(const CaptureThread&) = delete;

  // Asks the thread to finish and joins it (within about one grab timeout). Idempotent.
  void stop();
  bool running() const { return running_.load(); }
  // True once the source reported EndOfStream (and stop_at_end_of_stream is set).
  bool finished() const { return finished_.load(); }

  const CameraSource& source() const { return *source_; }
  CameraHealth health() const { return source_->health().snapshot(); }

 private:
  void run();
  bool connect();  // open + start; false (after logging) when that failed
  void disconnect(const std::string& why);
  void sleepInterruptibly(std::chrono::milliseconds duration);
  void publishStats() const;

  std::unique_ptr<CameraSource> source_;
  LatestFrameMailbox& mailbox_;
  CaptureOptions options_;
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> finished_{false};
  std::mutex sleep_mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace holo::capture
