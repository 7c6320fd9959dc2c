#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <regex>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/kiosk/health_server.hpp"
#include "holo/kiosk/health_status.hpp"
#include "holo/kiosk/listen_address.hpp"

namespace holo::kiosk {
namespace {

// Sends `request` as it is over a socket and returns the whole response.
std::string httpExchange(std::uint16_t port, const std::string& request) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return {};
  }
  EXPECT_EQ(send(fd, request.data(), request.size(), 0), static_cast<ssize_t>(request.size()));
  std::string response;
  char buffer[4096];
  ssize_t n;
  while ((n = recv(fd, buffer, sizeof buffer, 0)) > 0) response.append(buffer, static_cast<std::size_t>(n));
  close(fd);
  return response;
}

// A plain HTTP/1.0 GET, the way curl would do it; returns the whole response.
std::string httpGet(std::uint16_t port, const std::string& path) {
  return httpExchange(port, "GET " + path + " HTTP/1.0\r\nHost: localhost\r\n\r\n");
}

std::string bodyOf(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? std::string() : response.substr(end + 4);
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
    return sampleStatus();
  });
  ASSERT_NE(server.port(), 0);
  const std::string response = httpGet(server.port(), "/health");
  ASSERT_EQ(response.rfind("HTTP/1.1 200 OK", 0), 0u) << response;
  EXPECT_NE(response.find("Content-Type: application/json"), std::string::npos);
  EXPECT_NE(response.find("Cache-Control: no-store"), std::string::npos);
  const auto body = nlohmann::json::parse(bodyOf(response));
  EXPECT_EQ(body["quality"], "reduced");
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(httpGet(server.port(), "/nope").rfind("HTTP/1.1 404", 0), 0u);
  EXPECT_EQ(server.requestsServed(), 1);
}

TEST(HealthServer, ServesPrometheusMetrics) {
  HealthServer server("127.0.0.1", 0, [] { return sampleStatus(); });
  const std::string response = httpGet(server.port(), "/metrics");
  ASSERT_EQ(response.rfind("HTTP/1.1 200 OK", 0), 0u) << response;
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4"), std::string::npos) << response;
  const std::string body = bodyOf(response);
  EXPECT_NE(body.find("holopyramid_frames_per_second 24.94\n"), std::string::npos) << body;
  EXPECT_NE(body.find("holopyramid_camera_up{camera=\"cam1\"} 0\n"), std::string::npos) << body;
  EXPECT_NE(body.find("holopyramid_camera_dropped_frames_total{camera=\"cam1\"} 7\n"), std::string::npos);
  EXPECT_NE(body.find("holopyramid_camera_reconnects_total{camera=\"cam1\"} 3\n"), std::string::npos);
  EXPECT_NE(body.find("holopyramid_stage_seconds{stage=\"acquisition\"} 0.0035\n"), std::string::npos);
  EXPECT_NE(body.find("holopyramid_stage_seconds{stage=\"composition\"} +Inf\n"), std::string::npos);
  EXPECT_NE(body.find("holopyramid_config_fallback 1\n"), std::string::npos);
  EXPECT_NE(body.find("# TYPE holopyramid_frames_total counter\n"), std::string::npos);
  EXPECT_EQ(server.requestsServed(), 1);
}

TEST(HealthStatus, MetricsCarryTheQualityLevelTheTargetRateAndTheExhibitProblems) {
  HealthStatus h = sampleStatus();
  h.quality_level = 2;
  h.frame_budget_ms = 40;
  h.target_fps = 25;
  h.relic = "amphora";
  h.exhibit_problems = {"entry 3 (missing.glb): file not found"};
  const std::string text = h.toPrometheus();
  EXPECT_NE(text.find("\nholopyramid_quality_level 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nholopyramid_frame_budget_seconds 0.04\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nholopyramid_target_frames_per_second 25\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nholopyramid_exhibit_problems 1\n"), std::string::npos) << text;
  const nlohmann::json j = h.toJson();
  EXPECT_EQ(j["quality_level"], 2);
  EXPECT_EQ(j["relic"], "amphora");
  ASSERT_EQ(j["exhibit_problems"].size(), 1u);
  EXPECT_EQ(j["exhibit_problems"][0], "entry 3 (missing.glb): file not found");
}

TEST(HealthStatus, PrometheusLinesStayWellFormedWhateverTheNames) {
  HealthStatus h = sampleStatus();
  h.cameras[0].name = "a\"b\\c\nd} 1\nholopyramid_fake 9";
  h.stage_ms = {{"x\ny", 1.0}};
  h.fps = std::numeric_limits<double>::quiet_NaN();
  const std::string text = h.toPrometheus();
  EXPECT_NE(text.find("holopyramid_camera_up{camera=\"a\\\"b\\\\c\\nd} 1\\nholopyramid_fake 9\"} 1\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("holopyramid_frames_per_second NaN\n"), std::string::npos);
  // Every line is a comment or `name{labels} value`: no label value breaks out of its line.
  const std::regex sample(
      R"(holopyramid_[a-z_]+(\{([a-z]+="([^"\\]|\\.)*",?)+\})? (NaN|[+-]Inf|-?[0-9.e+-]+))");
  std::istringstream lines(text);
  int samples = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("# ", 0) == 0) continue;
    EXPECT_TRUE(std::regex_match(line, sample)) << line;
    ++samples;
  }
  EXPECT_GT(samples, 15);
  EXPECT_EQ(text.find("\nholopyramid_fake"), std::string::npos);
}

// A camera names itself (GigE cameras report their model) in no promised encoding: /metrics and
// the health JSON stay UTF-8, each invalid byte a U+FFFD, valid multi-byte names untouched.
// Before, nlohmann's dump() threw on such a name: /health answered 500 and the health file
// was not written.
TEST(HealthStatus, CameraNamesThatAreNotUtf8AreRepaired) {
  HealthStatus h = sampleStatus();
  const std::string replacement = "\xEF\xBF\xBD";
  h.cameras[0].name = "Kamera \xC3\xA4\xE2\x82\xAC";                       // "Kamera ä€": valid
  h.cameras[1].name = "cam\xFF\xC3(\xED\xA0\x80\xC0\xAF\xF4\x90\x80\x80";  // all invalid
  h.addError("read \xFE");
  const std::string text = h.toPrometheus();
  EXPECT_NE(text.find("holopyramid_camera_up{camera=\"Kamera \xC3\xA4\xE2\x82\xAC\"} "), std::string::npos)
      << text;
  std::string repaired = "cam" + replacement + replacement + "(";
  for (int i = 0; i < 3 + 2 + 4; ++i) repaired += replacement;  // a surrogate, an overlong '/', > U+10FFFF
  EXPECT_NE(text.find("holopyramid_camera_up{camera=\"" + repaired + "\"} "), std::string::npos) << text;
  const nlohmann::json j = h.toJson();
  EXPECT_NO_THROW((void)j.dump());
  EXPECT_EQ(j["cameras"][1]["name"], repaired);
  EXPECT_EQ(j["last_errors"].back(), "read " + replacement);
  EXPECT_NO_THROW((void)nlohmann::json(text).dump());  // the whole exposition is UTF-8
}

TEST(HealthServer, RefusesOtherMethodsAndRequestBodies) {
  HealthServer server("127.0.0.1", 0, [] { return sampleStatus(); });
  const std::string post =
      httpExchange(server.port(), "POST /health HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\n\r\nabc");
  EXPECT_EQ(post.rfind("HTTP/1.1 405", 0), 0u) << post;
  // Refused before the announced body is read: the server never waits for, nor holds, 100 MB.
  const std::string big =
      httpExchange(server.port(), "PUT /health HTTP/1.1\r\nHost: x\r\nContent-Length: 100000000\r\n\r\n");
  EXPECT_EQ(big.rfind("HTTP/1.1 405", 0), 0u) << big;
  const std::string junk = httpExchange(server.port(), std::string(9000, 'A') + "\r\n\r\n");
  EXPECT_EQ(junk.find("200 OK"), std::string::npos) << junk;
  EXPECT_EQ(server.requestsServed(), 0);
}

TEST(HealthServer, ASilentClientDoesNotBlockTheNext) {
  HealthServer server("127.0.0.1", 0, [] { return sampleStatus(); });
  const int silent = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(server.port());
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  ASSERT_EQ(connect(silent, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(httpGet(server.port(), "/health").rfind("HTTP/1.1 200 OK", 0), 0u);
  close(silent);
}

TEST(HealthServer, AProviderErrorIsA500NotACrash) {
  HealthServer server("127.0.0.1", 0, []() -> HealthStatus { throw Error("no status yet"); });
  const std::string response = httpGet(server.port(), "/metrics");
  EXPECT_EQ(response.rfind("HTTP/1.1 500", 0), 0u) << response;
  EXPECT_NE(response.find("no status yet"), std::string::npos);
  EXPECT_EQ(server.requestsServed(), 0);
}

TEST(HealthServer, RefusesNonLoopbackAddresses) {
  for (const char* address : {"0.0.0.0", "192.168.1.20", "::", "example.org", ""}) {
    try {
      HealthServer server(address, 0, [] { return HealthStatus{}; });
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
  HealthServer first("127.0.0.1", 0, [] { return HealthStatus{}; });
  EXPECT_THROW(HealthServer("127.0.0.1", first.port(), [] { return HealthStatus{}; }), Error);
}

}  // namespace
}  // namespace holo::kiosk
