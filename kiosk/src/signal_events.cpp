#include "holo/kiosk/signal_events.hpp"

#include <poll.h>
#include <pthread.h>
#include <sys/signalfd.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>

#include "holo/core/error.hpp"

namespace holo::kiosk {

SignalEvents::SignalEvents() {
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGTERM);
  sigaddset(&mask, SIGINT);
  sigaddset(&mask, SIGHUP);
  if (const int r = pthread_sigmask(SIG_BLOCK, &mask, &previous_mask_); r != 0)
    throw Error(std::string("cannot block signals: ") + std::strerror(r));
  fd_ = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
    throw Error(std::string("signalfd failed: ") + std::strerror(err));
  }
}

SignalEvents::~SignalEvents() {
  close(fd_);
  pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
}

std::vector<SignalEvent> SignalEvents::poll(std::chrono::milliseconds timeout) {
  std::vector<SignalEvent> events;
  pollfd pfd{fd_, POLLIN, 0};
  if (::poll(&pfd, 1, static_cast<int>(timeout.count())) <= 0) return events;
  signalfd_siginfo info{};
  while (read(fd_, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
    events.push_back(info.ssi_signo == SIGHUP ? SignalEvent::Reload : SignalEvent::Stop);
  }
  return events;
}

}  // namespace holo::kiosk
