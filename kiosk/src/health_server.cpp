#include "holo/kiosk/health_server.hpp"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::kiosk {
namespace {

std::string resolveName(const std::string& address) {
  return address == "localhost" ? "127.0.0.1" : address;
}

constexpr time_t kTimeoutS = 1;  // a client that connects and says nothing must not hold the worker

}  // namespace

bool isLoopbackAddress(const std::string& address) {
  const std::string name = resolveName(address);
  in_addr v4{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, name.c_str(), &v6) == 1) return IN6_IS_ADDR_LOOPBACK(&v6);
  return false;
}

bool isIpAddress(const std::string& address) {
  const std::string name = resolveName(address);
  in_addr v4{};
  in6_addr v6{};
  return inet_pton(AF_INET, name.c_str(), &v4) == 1 || inet_pton(AF_INET6, name.c_str(), &v6) == 1;
}

void addHealthRoutes(httplib::Server& server, HealthProvider provider,
                     std::shared_ptr<std::atomic<long>> served) {
  server.set_read_timeout(kTimeoutS, 0);
  server.set_write_timeout(kTimeoutS, 0);
  server.set_keep_alive_max_count(1);
  server.set_keep_alive_timeout(kTimeoutS);
  server.set_payload_max_length(0);
  // cpp-httplib's default also sets SO_REUSEPORT, which would let a second process share the
  // port and take some of the requests; a busy port must be an error instead.
  server.set_socket_options([](socket_t socket) {
    const int one = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  });
  server.set_default_headers({{"Cache-Control", "no-store"}});
  server.set_pre_routing_handler([](const httplib::Request& request, httplib::Response& response) {
    if (request.method == "GET" || request.method == "HEAD")
      return httplib::Server::HandlerResponse::Unhandled;
    response.status = 405;
    response.set_header("Allow", "GET, HEAD");
    response.set_content("GET only\n", "text/plain");
    return httplib::Server::HandlerResponse::Handled;
  });
  auto answer = [provider = std::move(provider), served = std::move(served)](httplib::Response& response,
                                                                             bool metrics) {
    const HealthStatus status = provider();
    if (metrics)
      response.set_content(status.toPrometheus(), "text/plain; version=0.0.4; charset=utf-8");
    else
      response.set_content(status.toJson().dump(2) + "\n", "application/json");
    ++*served;
  };
  server.Get("/",
             [answer](const httplib::Request&, httplib::Response& response) { answer(response, false); });
  server.Get("/health",
             [answer](const httplib::Request&, httplib::Response& response) { answer(response, false); });
  server.Get("/metrics",
             [answer](const httplib::Request&, httplib::Response& response) { answer(response, true); });
  server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
    if (response.status == 404) response.set_content("try /health or /metrics\n", "text/plain");
  });
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
        response.status = 500;
        std::string what = "unknown error";
        try {
          std::rethrow_exception(error);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        response.set_content(what + "\n", "text/plain");
      });
}

HealthServer::HealthServer(const std::string& address, std::uint16_t port, HealthProvider provider,
                           const std::string& field)
    : server_(std::make_unique<httplib::Server>()), served_(std::make_shared<std::atomic<long>>(0)) {
  if (!isLoopbackAddress(address))
    throw InputError("", field,
                     "a loopback address (127.0.0.1, localhost or ::1); the health endpoint never "
                     "listens on the museum network",
                     address);
  // A handful of local requests per minute: one worker is plenty and bounds what a flood costs.
  server_->new_task_queue = [] { return new httplib::ThreadPool(1); };
  addHealthRoutes(*server_, std::move(provider), served_);
  const std::string name = resolveName(address);
  errno = 0;
  if (port == 0) {
    const int bound = server_->bind_to_any_port(name);
    if (bound > 0) port_ = static_cast<std::uint16_t>(bound);
  } else if (server_->bind_to_port(name, port)) {
    port_ = port;
  }
  if (port_ == 0)
    throw Error("health server: cannot listen on " + address + ":" + std::to_string(port) + ": " +
                (errno != 0 ? std::strerror(errno) : "bind failed"));
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listening_ended_ = true;
  });
}

HealthServer::~HealthServer() {
  // cpp-httplib's stop() does nothing until the listening loop has started; wait for it so the
  // destructor never leaves the thread blocked in accept.
  while (!server_->is_running() && !listening_ended_)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace holo::kiosk
