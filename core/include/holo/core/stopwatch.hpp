// Wall time on the monotonic clock (std::chrono::steady_clock), as the project's stage times,
// evaluations and benchmarks report it: milliseconds or seconds as doubles.
#pragma once

#include <chrono>

namespace holo {

// Milliseconds from `start` to now.
inline double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Started on construction; restart() starts it again.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  double ms() const { return msSince(start_); }
  double seconds() const { return ms() / 1000.0; }
  std::chrono::steady_clock::time_point start() const { return start_; }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace holo
