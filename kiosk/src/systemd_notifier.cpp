#include "holo/kiosk/systemd_notifier.hpp"

#include <systemd/sd-daemon.h>
#include <cstdlib>

#include "holo/core/log.hpp"

namespace holo::kiosk {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket != nullptr && *socket != '\0';
  std::uint64_t usec = 0;
  // unset_environment = 0: sd_notify() reads NOTIFY_SOCKET on every call, so it must stay set.
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    watchdog_timeout_ = std::chrono::microseconds(static_cast<std::int64_t>(usec));
  }
}

void SystemdNotifier::send(const std::string& message) {
  if (!enabled_) return;
  const int r = sd_notify(0, message.c_str());
  if (r < 0) {
    HOLO_LOG_WARN("sd_notify(\"{}\") failed: error {}", message.substr(0, message.find('\n')), -r);
    return;
  }
  ++sent_;
}

void SystemdNotifier::ready(const std::string& status) {
  last_status_ = status;
  send("READY=1\nSTATUS=" + status);
}

void SystemdNotifier::watchdog() {
  send("WATCHDOG=1");
}

void SystemdNotifier::status(const std::string& status) {
  if (status == last_status_) return;
  last_status_ = status;
  send("STATUS=" + status);
}

void SystemdNotifier::reloading() {
  send("RELOADING=1");
}

void SystemdNotifier::stopping() {
  send("STOPPING=1");
}

}  // namespace holo::kiosk
