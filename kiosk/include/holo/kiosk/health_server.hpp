// The kiosk's health over HTTP on the loopback interface only, served by cpp-httplib:
//   GET /health   the HealthStatus as JSON (application/json)
//   GET /metrics  the same figures in the Prometheus text exposition format 0.0.4
// Loopback only because the appliance sits in a public hall: nothing on the museum network may
// read or poke it; a technician or the museum's monitoring reaches it on the machine or through
// an SSH tunnel.
//
// Limits against a hostile or broken client: GET and HEAD only, no request body accepted, request
// line and headers capped by cpp-httplib (8 KiB each), 1 s read and write timeouts, one worker
// thread, one request per connection.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "holo/kiosk/health_status.hpp"

namespace httplib {
class Server;
}

namespace holo::kiosk {

class HttpListener;  // kiosk/src/http_listener.hpp

using HealthProvider = std::function<HealthStatus()>;

class HealthServer {
 public:
  // Binds `address`:`port` (port 0 picks a free port, see port()). Throws InputError naming
  // `field` when the address is not a loopback address (127.0.0.0/8, "localhost" or ::1), and
  // holo::Error when the port cannot be bound.
  HealthServer(const std::string& address, std::uint16_t port, HealthProvider provider,
               const std::string& field = "kiosk.health.address");
  ~HealthServer();
  HealthServer(const HealthServer&) = delete;
  HealthServer& operator=(const HealthServer&) = delete;

  std::uint16_t port() const;
  // Successful /health and /metrics answers so far.
  long requestsServed() const { return served_->load(); }

 private:
  std::shared_ptr<std::atomic<long>> served_;
  std::unique_ptr<HttpListener> listener_;
};

// Installs the /health and /metrics routes, the limits above and the error answers on `server`;
// `served` counts successful answers. HealthServer uses it; so does the fuzz target, which feeds
// raw bytes through the same routes without a socket.
void addHealthRoutes(httplib::Server& server, HealthProvider provider,
                     std::shared_ptr<std::atomic<long>> served);

}  // namespace holo::kiosk
