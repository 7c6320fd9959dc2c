#include "http_listener.hpp"

#include <sys/socket.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "holo/core/error.hpp"
#include "holo/kiosk/listen_address.hpp"

namespace holo::kiosk {

void setConnectionLimits(httplib::Server& server, std::time_t timeout_s, std::size_t max_body_bytes) {
  server.set_read_timeout(timeout_s, 0);
  server.set_write_timeout(timeout_s, 0);
  server.set_keep_alive_max_count(1);
  server.set_keep_alive_timeout(timeout_s);
  server.set_payload_max_length(max_body_bytes);
  server.set_socket_options([](socket_t socket) {
    const int one = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  });
}

std::string exceptionMessage(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
  return "unknown error";
}

HttpListener::HttpListener(std::unique_ptr<httplib::Server> server, const std::string& service,
                           const std::string& address, std::uint16_t port)
    : server_(std::move(server)) {
  const std::string name = bindableAddress(address);
  errno = 0;
  if (port == 0) {
    const int bound = server_->bind_to_any_port(name);
    if (bound > 0) port_ = static_cast<std::uint16_t>(bound);
  } else if (server_->bind_to_port(name, port)) {
    port_ = port;
  }
  if (port_ == 0)
    throw Error(service + ": cannot listen on " + address + ":" + std::to_string(port) + ": " +
                (errno != 0 ? std::strerror(errno) : "bind failed"));
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listening_ended_ = true;
  });
}

HttpListener::~HttpListener() {
  // cpp-httplib's stop() does nothing until the listening loop has started; wait for it so the
  // destructor never leaves the thread blocked in accept.
  while (!server_->is_running() && !listening_ended_)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace holo::kiosk
