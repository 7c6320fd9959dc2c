#include "holo/kiosk/health_server.hpp"

#include <httplib.h>

#include "holo/core/error.hpp"
#include "holo/kiosk/listen_address.hpp"
#include "http_listener.hpp"

namespace holo::kiosk {
namespace {

constexpr time_t kTimeoutS = 1;  // a client that connects and says nothing must not hold the worker

}  // namespace

void addHealthRoutes(httplib::Server& server, HealthProvider provider,
                     std::shared_ptr<std::atomic<long>> served) {
  setConnectionLimits(server, kTimeoutS, 0);
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
        response.set_content(exceptionMessage(error) + "\n", "text/plain");
      });
}

HealthServer::HealthServer(const std::string& address, std::uint16_t port, HealthProvider provider,
                           const std::string& field)
    : served_(std::make_shared<std::atomic<long>>(0)) {
  if (!isLoopbackAddress(address))
    throw InputError("", field,
                     "a loopback address (127.0.0.1, localhost or ::1); the health endpoint never "
                     "listens on the museum network",
                     address);
  auto server = std::make_unique<httplib::Server>();
  // A handful of local requests per minute: one worker is plenty and bounds what a flood costs.
  server->new_task_queue = [] { return new httplib::ThreadPool(1); };
  addHealthRoutes(*server, std::move(provider), served_);
  listener_ = std::make_unique<HttpListener>(std::move(server), "health server", address, port);
}

HealthServer::~HealthServer() = default;

std::uint16_t HealthServer::port() const {
  return listener_->port();
}

}  // namespace holo::kiosk
