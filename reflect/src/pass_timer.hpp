// Times one frame-renderer pass, from construction to destruction, into a list of PassTiming.
#pragma once

#include <chrono>
#include <vector>

#include "holo/reflect/pass_timing.hpp"

namespace holo::reflect {

class PassTimer {
 public:
  PassTimer(std::vector<PassTiming>& out, Pass pass)
      : out_(out), pass_(pass), start_(std::chrono::steady_clock::now()) {}
  ~PassTimer() {
    const auto end = std::chrono::steady_clock::now();
    out_.push_back({pass_, std::chrono::duration<double, std::milli>(end - start_).count() - subtracted_ms_});
  }
  // Time spent inside the pass that another pass accounts for (milliseconds).
  void subtract(double ms) { subtracted_ms_ += ms; }
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

 private:
  std::vector<PassTiming>& out_;
  Pass pass_;
  std::chrono::steady_clock::time_point start_;
  double subtracted_ms_ = 0.0;
};

}  // namespace holo::reflect
