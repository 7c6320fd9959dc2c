#include "holo/kiosk/console_server.hpp"

#include <httplib.h>

#include <nlohmann/json.hpp>

#include "console_assets.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/kiosk/listen_address.hpp"
#include "http_listener.hpp"

namespace holo::kiosk {
namespace {

constexpr time_t kTimeoutS = 2;
constexpr const char* kCookie = "holo_session";

std::string sessionCookie(const httplib::Request& request) {
  // Cookie: a=b; holo_session=...; c=d
  const std::string prefix = std::string(kCookie) + "=";
  for (auto [it, end] = request.headers.equal_range("Cookie"); it != end; ++it) {
    const std::string& header = it->second;
    for (std::size_t start = 0; start < header.size();) {
      std::size_t stop = header.find(';', start);
      if (stop == std::string::npos) stop = header.size();
      std::size_t first = start;
      while (first < stop && header[first] == ' ') ++first;
      if (header.compare(first, prefix.size(), prefix) == 0)
        return header.substr(first + prefix.size(), stop - first - prefix.size());
      start = stop + 1;
    }
  }
  return {};
}

void text(httplib::Response& response, int status, const std::string& body) {
  response.status = status;
  response.set_content(body + "\n", "text/plain; charset=utf-8");
}

void json(httplib::Response& response, int status, const nlohmann::json& body) {
  response.status = status;
  response.set_content(body.dump() + "\n", "application/json");
}

std::string page(std::string html, const std::string& key, const std::string& value) {
  const std::string marker = "{{" + key + "}}";
  for (std::size_t at = html.find(marker); at != std::string::npos; at = html.find(marker, at + value.size()))
    html.replace(at, marker.size(), value);
  return html;
}

std::string loginPage(const std::string& message) {
  return page(std::string(console_assets::kLoginHtml), "MESSAGE", message);
}

// The request comes from a page of this console, as far as the browser says: an Origin header,
// when sent, must name the host the request was sent to.
bool sameOrigin(const httplib::Request& request) {
  if (!request.has_header("Origin")) return true;
  return request.get_header_value("Origin") == "http://" + request.get_header_value("Host");
}

struct Routes {
  std::shared_ptr<ConsoleAuth> auth;
  ConsoleBackend backend;

  // The live session of the request, or an answer (401) and empty.
  std::string requireSession(const httplib::Request& request, httplib::Response& response) const {
    const std::string id = sessionCookie(request);
    if (!id.empty() && auth->csrfToken(id)) return id;
    json(response, 401, {{"error", "log in first"}});
    return {};
  }
  // A session and its CSRF token, else 401 or 403 answered and false.
  bool requireAction(const httplib::Request& request, httplib::Response& response) const {
    const std::string id = requireSession(request, response);
    if (id.empty()) return false;
    std::string token = request.get_header_value("X-CSRF-Token");
    if (token.empty()) token = request.get_param_value("csrf");
    if (!sameOrigin(request) || !auth->csrfMatches(id, token)) {
      HOLO_LOG_WARN("console: {} {} from {} refused: wrong CSRF token or origin", request.method,
                    request.path, request.remote_addr);
      json(response, 403, {{"error", "wrong or missing CSRF token"}});
      return false;
    }
    return true;
  }
};

}  // namespace

void addConsoleRoutes(httplib::Server& server, std::shared_ptr<ConsoleAuth> auth, ConsoleBackend backend) {
  auto routes = std::make_shared<const Routes>(Routes{std::move(auth), std::move(backend)});
  setConnectionLimits(server, kTimeoutS, ConsoleServer::kMaxBodyBytes);
  server.set_default_headers({
      {"Cache-Control", "no-store"},
      {"X-Content-Type-Options", "nosniff"},
      {"X-Frame-Options", "DENY"},
      {"Referrer-Policy", "same-origin"},  // no-referrer would make Chromium send "Origin: null"
      {"Content-Security-Policy",
       "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self'; connect-src 'self'; "
       "form-action 'self'; frame-ancestors 'none'; base-uri 'none'"},
  });
  server.set_pre_routing_handler([](const httplib::Request& request, httplib::Response& response) {
    if (request.method != "GET" && request.method != "HEAD" && request.method != "POST") {
      response.set_header("Allow", "GET, HEAD, POST");
      text(response, 405, "GET, HEAD and POST only");
      return httplib::Server::HandlerResponse::Handled;
    }
    std::size_t header_bytes = 0;
    for (const auto& [name, value] : request.headers) header_bytes += name.size() + value.size() + 4;
    if (header_bytes > ConsoleServer::kMaxHeaderBytes) {
      text(response, 431, "request headers too large");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });

  server.Get("/", [routes](const httplib::Request& request, httplib::Response& response) {
    const std::string id = sessionCookie(request);
    const auto csrf = id.empty() ? std::nullopt : routes->auth->csrfToken(id);
    if (!csrf) {
      response.set_content(loginPage(""), "text/html; charset=utf-8");
      return;
    }
    response.set_content(page(std::string(console_assets::kStatusHtml), "CSRF", *csrf),
                         "text/html; charset=utf-8");
  });
  server.Get("/console.js", [](const httplib::Request&, httplib::Response& response) {
    response.set_content(std::string(console_assets::kConsoleJs), "text/javascript; charset=utf-8");
  });
  server.Get("/console.css", [](const httplib::Request&, httplib::Response& response) {
    response.set_content(std::string(console_assets::kConsoleCss), "text/css; charset=utf-8");
  });
  server.Post("/login", [routes](const httplib::Request& request, httplib::Response& response) {
    if (!sameOrigin(request)) {
      response.status = 403;
      response.set_content(loginPage("This login came from another site and was refused."),
                           "text/html; charset=utf-8");
      return;
    }
    const ConsoleAuth::Login login =
        routes->auth->login(request.remote_addr, request.get_param_value("password"));
    switch (login.outcome) {
      case ConsoleAuth::Outcome::Ok:
        HOLO_LOG_INFO("console: login from {}", request.remote_addr);
        response.set_header("Set-Cookie", std::string(kCookie) + "=" + login.session_id +
                                              "; Path=/; HttpOnly; SameSite=Strict");
        response.set_redirect("/", 303);
        return;
      case ConsoleAuth::Outcome::WrongPassword:
        HOLO_LOG_WARN("console: wrong password from {}", request.remote_addr);
        response.status = 401;
        response.set_content(loginPage("Wrong password."), "text/html; charset=utf-8");
        return;
      case ConsoleAuth::Outcome::RateLimited:
        HOLO_LOG_WARN("console: login from {} refused: too many wrong passwords", request.remote_addr);
        response.status = 429;
        response.set_header("Retry-After", std::to_string(login.retry_after_s));
        response.set_content(loginPage("Too many wrong passwords: try again in " +
                                       std::to_string(login.retry_after_s) + " s."),
                             "text/html; charset=utf-8");
        return;
    }
  });
  server.Post("/logout", [routes](const httplib::Request& request, httplib::Response& response) {
    if (!routes->requireAction(request, response)) return;
    routes->auth->logout(sessionCookie(request));
    HOLO_LOG_INFO("console: logout from {}", request.remote_addr);
    response.set_header("Set-Cookie",
                        std::string(kCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0");
    response.set_redirect("/", 303);
  });
  server.Get("/api/status", [routes](const httplib::Request& request, httplib::Response& response) {
    const std::string id = routes->requireSession(request, response);
    if (id.empty()) return;
    json(response, 200,
         {{"health", routes->backend.health().toJson()},
          {"log", routes->backend.log_tail()},
          {"session_s", routes->auth->secondsLeft(id)}});
  });
  const auto snapshot = [routes](SnapshotKind kind, int count) {
    return [routes, kind, count](const httplib::Request& request, httplib::Response& response) {
      if (routes->requireSession(request, response).empty()) return;
      const int index = std::stoi(request.matches[1].str());
      if (index >= count) return text(response, 404, "no such snapshot");
      const std::string jpeg = routes->backend.snapshot_jpeg(kind, index);
      if (jpeg.empty()) {
        response.set_header("Retry-After", "1");
        return text(response, 503, "no picture yet");
      }
      response.set_content(jpeg, "image/jpeg");
    };
  };
  server.Get(R"(/snapshot/face/([0-3])\.jpg)", snapshot(SnapshotKind::Face, 4));
  server.Get(R"(/snapshot/camera/([0-9]|1[0-5])\.jpg)", snapshot(SnapshotKind::Camera, 16));
  for (const KioskAction action : {KioskAction::NextRelic, KioskAction::RelearnBackground}) {
    server.Post("/api/action/" + kioskActionName(action),
                [routes, action](const httplib::Request& request, httplib::Response& response) {
                  if (!routes->requireAction(request, response)) return;
                  if (!routes->backend.act(action))
                    return json(response, 503, {{"error", "too many requests pending; try again"}});
                  HOLO_LOG_INFO("console: {} asked from {}", kioskActionName(action), request.remote_addr);
                  json(response, 202, {{"accepted", kioskActionName(action)}});
                });
  }
  server.Post("/api/action/reload", [routes](const httplib::Request& request, httplib::Response& response) {
    if (!routes->requireAction(request, response)) return;
    HOLO_LOG_INFO("console: reload asked from {}", request.remote_addr);
    routes->backend.reload();
    json(response, 202, {{"accepted", "reload"}});
  });

  server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
    if (response.status == 404 && response.body.empty()) text(response, 404, "not found");
    if (response.status == 413) text(response, 413, "request body too large");
  });
  server.set_exception_handler(
      [](const httplib::Request& request, httplib::Response& response, std::exception_ptr error) {
        HOLO_LOG_ERROR("console: {} {}: {}", request.method, request.path, exceptionMessage(error));
        text(response, 500, "internal error");
      });
}

ConsoleServer::ConsoleServer(const std::string& address, std::uint16_t port,
                             std::shared_ptr<ConsoleAuth> auth, ConsoleBackend backend,
                             const std::string& field) {
  if (!isIpAddress(address))
    throw InputError("", field, "an IP address to listen on (127.0.0.1 = this machine only)", address);
  auto server = std::make_unique<httplib::Server>();
  server->new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
  addConsoleRoutes(*server, std::move(auth), std::move(backend));
  listener_ = std::make_unique<HttpListener>(std::move(server), "console", address, port);
}

ConsoleServer::~ConsoleServer() = default;

std::uint16_t ConsoleServer::port() const {
  return listener_->port();
}

}  // namespace holo::kiosk
