// The health JSON over HTTP on the loopback interface only: `curl http://127.0.0.1:PORT/health`.
// Loopback only because the appliance sits in a public hall: nothing on the museum network may
// read or poke it; a technician reaches it on the machine or through an SSH tunnel.
//
// A tiny blocking HTTP/1.0 server on its own thread: one request at a time, GET only, the body
// is whatever `provider` returns. Debian ships no small embeddable C++ HTTP server library that
// the project already depends on, and this answers a handful of local requests per minute.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace holo::kiosk {

class HealthServer {
 public:
  // Binds `address`:`port` (port 0 picks a free port, see port()). Throws InputError naming
  // `field` when the address is not a loopback address (127.0.0.0/8, "localhost" or ::1), and
  // holo::Error when the port cannot be bound.
  HealthServer(const std::string& address, std::uint16_t port, std::function<std::string()> provider,
               const std::string& field = "kiosk.health.address");
  ~HealthServer();
  HealthServer(const HealthServer&) = delete;
  HealthServer& operator=(const HealthServer&) = delete;

  std::uint16_t port() const { return port_; }
  long requestsServed() const { return served_.load(); }

 private:
  void serve();
  int listen_fd_ = -1;
  int wake_pipe_[2] = {-1, -1};  // written by the destructor to end serve()
  std::uint16_t port_ = 0;
  std::function<std::string()> provider_;
  std::atomic<long> served_{0};
  std::thread thread_;
};

// True for the addresses HealthServer accepts.
bool isLoopbackAddress(const std::string& address);

}  // namespace holo::kiosk
