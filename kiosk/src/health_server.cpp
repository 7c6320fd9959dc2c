#include "holo/kiosk/health_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::kiosk {
namespace {

std::string resolveName(const std::string& address) {
  return address == "localhost" ? "127.0.0.1" : address;
}

void sendAll(int fd, const std::string& data) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::send(fd, data.data() + done, data.size() - done, MSG_NOSIGNAL);
    if (n <= 0) return;  // the client went away; nothing to repair
    done += static_cast<std::size_t>(n);
  }
}

std::string response(int code, const char* reason, const std::string& type, const std::string& body) {
  return "HTTP/1.0 " + std::to_string(code) + " " + reason + "\r\nContent-Type: " + type +
         "\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n" + body;
}

}  // namespace

bool isLoopbackAddress(const std::string& address) {
  const std::string name = resolveName(address);
  in_addr v4{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, name.c_str(), &v6) == 1) return IN6_IS_ADDR_LOOPBACK(&v6);
  return false;
}

HealthServer::HealthServer(const std::string& address, std::uint16_t port,
                           std::function<std::string()> provider, const std::string& field)
    : provider_(std::move(provider)) {
  if (!isLoopbackAddress(address))
    throw InputError("", field,
                     "a loopback address (127.0.0.1, localhost or ::1); the health endpoint never "
                     "listens on the museum network",
                     address);
  const std::string name = resolveName(address);
  sockaddr_storage storage{};
  socklen_t length = 0;
  int family = AF_INET;
  if (auto* v4 = reinterpret_cast<sockaddr_in*>(&storage);
      inet_pton(AF_INET, name.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(port);
    length = sizeof(sockaddr_in);
  } else {
    auto* v6 = reinterpret_cast<sockaddr_in6*>(&storage);
    inet_pton(AF_INET6, name.c_str(), &v6->sin6_addr);
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(port);
    length = sizeof(sockaddr_in6);
    family = AF_INET6;
  }
  listen_fd_ = ::socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw Error(std::string("health server: socket: ") + std::strerror(errno));
  const int one = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&storage), length) != 0 ||
      ::listen(listen_fd_, 8) != 0) {
    const int err = errno;
    ::close(listen_fd_);
    throw Error("health server: cannot listen on " + address + ":" + std::to_string(port) + ": " +
                std::strerror(err));
  }
  sockaddr_storage bound{};
  socklen_t bound_length = sizeof bound;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &bound_length);
  port_ = ntohs(family == AF_INET ? reinterpret_cast<sockaddr_in*>(&bound)->sin_port
                                  : reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port);
  if (::pipe2(wake_pipe_, O_CLOEXEC) != 0) {
    ::close(listen_fd_);
    throw Error(std::string("health server: pipe: ") + std::strerror(errno));
  }
  thread_ = std::thread([this] { serve(); });
}

HealthServer::~HealthServer() {
  const char byte = 'x';
  [[maybe_unused]] const ssize_t n = ::write(wake_pipe_[1], &byte, 1);
  if (thread_.joinable()) thread_.join();
  ::close(listen_fd_);
  ::close(wake_pipe_[0]);
  ::close(wake_pipe_[1]);
}

void HealthServer::serve() {
  for (;;) {
    pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {wake_pipe_[0], POLLIN, 0}};
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      HOLO_LOG_ERROR("health server: poll: {}", std::strerror(errno));
      return;
    }
    if (fds[1].revents != 0) return;
    const int client = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    // A client that connects and says nothing must not block the server for long.
    timeval timeout{1, 0};
    setsockopt(client, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    setsockopt(client, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    std::string request;
    char buffer[1024];
    while (request.find("\r\n\r\n") == std::string::npos && request.size() < 8192) {
      const ssize_t n = ::recv(client, buffer, sizeof buffer, 0);
      if (n <= 0) break;
      request.append(buffer, static_cast<std::size_t>(n));
    }
    const auto line_end = request.find("\r\n");
    const std::string line = request.substr(0, line_end);
    if (line.rfind("GET /health ", 0) == 0 || line.rfind("GET / ", 0) == 0) {
      std::string body;
      try {
        body = provider_();
      } catch (const std::exception& e) {
        sendAll(client, response(500, "Internal Server Error", "text/plain", e.what()));
        ::close(client);
        continue;
      }
      sendAll(client, response(200, "OK", "application/json", body + "\n"));
      ++served_;
    } else if (line.rfind("GET ", 0) == 0) {
      sendAll(client, response(404, "Not Found", "text/plain", "try /health\n"));
    } else {
      sendAll(client, response(405, "Method Not Allowed", "text/plain", "GET only\n"));
    }
    ::close(client);
  }
}

}  // namespace holo::kiosk
