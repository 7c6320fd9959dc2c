// Progress of a long operation. On a terminal it draws a bar with a rate and an estimate of the
// time left on stderr, at most ten times a second; otherwise (CI, logs, tests) it prints one line
// at the start and one at the end. update() is thread-safe and cheap (one atomic add).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace holo {

class ProgressReporter {
 public:
  ProgressReporter(std::int64_t total_work, std::string title, bool quiet = false);
  ~ProgressReporter();  // calls done() if the caller did not
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  void update(std::int64_t work = 1);
  void done();
  double elapsedSeconds() const;

 private:
  void draw(bool final);
  std::int64_t total_;
  std::string title_;
  bool quiet_;
  bool tty_;
  std::atomic<std::int64_t> done_work_{0};
  std::atomic<bool> finished_{false};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex draw_mutex_;
};

}  // namespace holo
