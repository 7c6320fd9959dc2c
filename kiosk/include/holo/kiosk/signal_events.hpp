// SIGTERM, SIGINT and SIGHUP as events the frame loop polls between frames (signalfd(2)), so no
// work ever runs in a signal handler. The constructor blocks the three signals for the calling
// thread; create SignalEvents before starting any other thread so every thread inherits the
// block and the signals queue on the descriptor instead of killing the process. The destructor
// restores the previous mask.
#pragma once

#include <chrono>
#include <csignal>
#include <vector>

namespace holo::kiosk {

enum class SignalEvent { Stop, Reload };

class SignalEvents {
 public:
  SignalEvents();
  ~SignalEvents();
  SignalEvents(const SignalEvents&) = delete;
  SignalEvents& operator=(const SignalEvents&) = delete;

  // Events that arrived, in order, waiting at most `timeout` for the first (0: do not wait).
  // SIGTERM and SIGINT give Stop, SIGHUP gives Reload.
  std::vector<SignalEvent> poll(std::chrono::milliseconds timeout = std::chrono::milliseconds(0));

 private:
  int fd_ = -1;
  sigset_t previous_mask_{};
};

}  // namespace holo::kiosk
