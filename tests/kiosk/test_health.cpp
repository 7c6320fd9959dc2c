#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/kiosk/health_server.hpp"
#include "holo/kiosk/health_status.hpp"

namespace holo::kiosk {
namespace {

// A plain HTTP/1.0 GET over a socket, the way curl would do it; returns the whole response.
std::string httpGet(std::uint16_t port, const std::string& path) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return {};
  }
  const std::string request = "GET " + path + " HTTP/1.0\r\nHost: localhost\r\n\r\n";
  EXPECT_EQ(send(fd, request.data(), request.size(), 0), static_cast<ssize_t>(request.size()));
  std::string response;
  char buffer[4096];
  ssize_t n;
  while ((n = recv(fd, buffer, sizeof buffer, 0)) > 0) response.append(buffer, static_cast<std::size_t>(n));
  close(fd);
  return response;
}

HealthStatus sampleStatus() {
  HealthStatus h;
  h.state = "running";
  h.mode = "partial";
  h.quality = "reduced";
  h.fps = 24.94;
  h.stage_ms = {{"acquisition", 3.5}, {"composition", std::numeric_limits<double>::infinity()}};
  h.foreground_share = 0.123;
  h.cameras = {{"cam0", true, 100, 2, 0, 0.04}, {"cam1", false, 50, 7, 3, 12.5}};
  h.config_source = "factory defaults";
  h.config_warning = "using factory defaults: x.yaml: line 3: bad\nindent";
  return h;
}

TEST(HealthStatus, JsonCarriesCountersAndStaysValidWithInfinity) {
  const auto j = nlohmann::json::parse(sampleStatus().toJson().dump());
  EXPECT_EQ(j["mode"], "partial");
  EXPECT_EQ(j["cameras"].size(), 2u);
  EXPECT_EQ(j["cameras"][1]["reconnects"], 3);
  EXPECT_EQ(j["cameras"][1]["dropped"], 7);
  EXPECT_EQ(j["cameras_alive"], 1);
  EXPECT_DOUBLE_EQ(j["stage_ms"]["acquisition"].get<double>(), 3.5);
  EXPECT_DOUBLE_EQ(j["stage_ms"]["composition"].get<double>(), -1.0);  // Inf is not JSON
  EXPECT_EQ(j["config"]["source"], "factory defaults");
}

TEST(HealthStatus, SummaryIsOneLineWithTheIssueFields) {
  const std::string s = sampleStatus().summary();
  EXPECT_EQ(s.find('\n'), std::string::npos);
  EXPECT_NE(s.find("cameras 1/2"), std::string::npos) << s;
  EXPECT_NE(s.find("24.9 fps"), std::string::npos) << s;
  EXPECT_NE(s.find("fg 12%"), std::string::npos) << s;
  EXPECT_NE(s.find("mode partial"), std::string::npos) << s;
  EXPECT_NE(s.find("CONFIG: using factory defaults"), std::string::npos) << s;
}

TEST(HealthStatus, KeepsOnlyTheLastErrors) {
  HealthStatus h;
  for (int i = 0; i < 25; ++i) {
    std::string message = "e";  // built in two steps: GCC 12 warns falsely on "e" + to_string
    message += std::to_string(i);
    h.addError(message);
  }
  ASSERT_EQ(h.last_errors.size(), HealthStatus::kMaxErrors);
  EXPECT_EQ(h.last_errors.front(), "e15");
  EXPECT_EQ(h.last_errors.back(), "e24");
}

TEST(HealthServer, AnswersOnLoopbackWithJson) {
  int calls = 0;
  HealthServer server("127.0.0.1", 0, [&] {
    ++calls;
    return sampleStatus().toJson().dump();
  });
  ASSERT_NE(server.port(), 0);
  const std::string response = httpGet(server.port(), "/health");
  ASSERT_EQ(response.rfind("HTTP/1.0 200 OK", 0), 0u) << response;
  EXPECT_NE(response.find("Content-Type: application/json"), std::string::npos);
  const auto body = nlohmann::json::parse(response.substr(response.find("\r\n\r\n") + 4));
  EXPECT_EQ(body["quality"], "reduced");
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(httpGet(server.port(), "/nope").rfind("HTTP/1.0 404", 0), 0u);
  EXPECT_EQ(server.requestsServed(), 1);
}

TEST(HealthServer, RefusesNonLoopbackAddresses) {
  for (const char* address : {"0.0.0.0", "192.168.1.20", "::", "example.org", ""}) {
    try {
      HealthServer server(address, 0, [] { return std::string("{}"); });
      ADD_FAILURE() << "bound " << address;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("kiosk.health.address"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(isLoopbackAddress("127.0.0.1"));
  EXPECT_TRUE(isLoopbackAddress("127.1.2.3"));
  EXPECT_TRUE(isLoopbackAddress("localhost"));
  EXPECT_TRUE(isLoopbackAddress("::1"));
  EXPECT_FALSE(isLoopbackAddress("128.0.0.1"));
}

TEST(HealthServer, BusyPortIsAnErrorNotACrash) {
  HealthServer first("127.0.0.1", 0, [] { return std::string("{}"); });
  EXPECT_THROW(HealthServer("127.0.0.1", first.port(), [] { return std::string("{}"); }), Error);
}

}  // namespace
}  // namespace holo::kiosk
