// One cpp-httplib server bound to an address and served on a thread of its own: the health
// endpoint and the technician's console each own one, with their own routes and limits.
#pragma once

#include <httplib.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <exception>
#include <memory>
#include <string>
#include <thread>

namespace holo::kiosk {

// The limits every kiosk listener sets: `timeout_s` to read and to write a request, one request
// per connection, request bodies up to `max_body_bytes` (0: none), and SO_REUSEADDR without
// cpp-httplib's default SO_REUSEPORT, which would let a second process share the port and take
// some of the requests (a busy port must be an error instead).
void setConnectionLimits(httplib::Server& server, std::time_t timeout_s, std::size_t max_body_bytes);

// The message of the exception a route threw, for the 500 answer and the log.
std::string exceptionMessage(const std::exception_ptr& error);

class HttpListener {
 public:
  // Binds bindableAddress(`address`):`port` (0 = any free port, see port()) and starts serving
  // `server`'s routes, which must be installed already. Throws holo::Error starting with
  // `service` when the port cannot be bound.
  HttpListener(std::unique_ptr<httplib::Server> server, const std::string& service,
               const std::string& address, std::uint16_t port);
  // Stops serving; requests in progress finish first.
  ~HttpListener();
  HttpListener(const HttpListener&) = delete;
  HttpListener& operator=(const HttpListener&) = delete;

  std::uint16_t port() const { return port_; }

 private:
  std::unique_ptr<httplib::Server> server_;
  std::uint16_t port_ = 0;
  std::atomic<bool> listening_ended_{false};
  std::thread thread_;
};

}  // namespace holo::kiosk
