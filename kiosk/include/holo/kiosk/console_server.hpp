// The technician's web console (docs/kiosk.md, "The technician's console"; threat model in
// docs/security.md), served by cpp-httplib on its own listener (kiosk.console: address and
// port), apart from the loopback-only health endpoint:
//   GET  /                          the login page, or with a session the status page
//   GET  /console.js, /console.css  the page's assets (built into the program)
//   POST /login                     form field `password`: a session cookie and 303 to /
//   POST /logout                    ends the session (CSRF token required)
//   GET  /api/status                {"health": the /health JSON, "log": the log's tail,
//                                    "session_s": seconds the session has left}
//   GET  /snapshot/face/N.jpg       N = 0..3, the face as shown (JPEG)
//   GET  /snapshot/camera/N.jpg     N = 0..15, the camera's colour image (JPEG)
//   POST /api/action/next-relic, /api/action/relearn-background, /api/action/reload
// Everything but the login page, its assets and /login needs a session (401 without); every POST
// but /login needs the session's CSRF token in the X-CSRF-Token header or the `csrf` form field
// (403 without), and a POST whose Origin header names another site is refused (403).
//
// Limits: GET, HEAD and POST only (405 else); request bodies up to kMaxBodyBytes (413), all
// header lines together up to kMaxHeaderBytes (431), the request line and each header line up to
// cpp-httplib's 8 KiB; 2 s read and write timeouts; one request per connection; kWorkers
// threads. Unknown paths, path traversal included, are 404: no route reads a file.
// Login limits: console_auth.hpp. Every answer carries no-store, nosniff, frame-deny and a
// same-origin Content-Security-Policy; the session cookie is HttpOnly and SameSite=Strict.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "holo/kiosk/console_auth.hpp"
#include "holo/kiosk/health_status.hpp"
#include "holo/kiosk/kiosk_action.hpp"

namespace httplib {
class Server;
}

namespace holo::kiosk {

class HttpListener;  // kiosk/src/http_listener.hpp

enum class SnapshotKind { Face, Camera };

// What the console shows and does; KioskLoop provides it. Called on the server's threads.
struct ConsoleBackend {
  std::function<HealthStatus()> health;
  std::function<std::vector<std::string>()> log_tail;  // oldest first
  std::function<bool(KioskAction)> act;                // false: too many requests pending
  std::function<void()> reload;                        // as SIGHUP
  // The JPEG of face or camera `index`; empty when there is none (yet). Asking is what makes the
  // frame source take snapshots for a while (KioskLoop).
  std::function<std::string(SnapshotKind, int)> snapshot_jpeg;
};

class ConsoleServer {
 public:
  static constexpr std::size_t kMaxBodyBytes = 4096;
  static constexpr std::size_t kMaxHeaderBytes = 8192;
  static constexpr int kWorkers = 4;

  // Binds `address`:`port` (0 = any free port, see port()). Throws InputError naming `field`
  // when `address` is not an IP address, holo::Error when the port cannot be bound.
  ConsoleServer(const std::string& address, std::uint16_t port, std::shared_ptr<ConsoleAuth> auth,
                ConsoleBackend backend, const std::string& field = "kiosk.console.address");
  ~ConsoleServer();
  ConsoleServer(const ConsoleServer&) = delete;
  ConsoleServer& operator=(const ConsoleServer&) = delete;

  std::uint16_t port() const;

 private:
  std::unique_ptr<HttpListener> listener_;
};

// Installs the routes, limits and error answers above on `server` (ConsoleServer and the fuzz
// target, which feeds raw bytes through them without a socket).
void addConsoleRoutes(httplib::Server& server, std::shared_ptr<ConsoleAuth> auth, ConsoleBackend backend);

}  // namespace holo::kiosk
