// The technician's console: its configuration, the secret file, sessions and the login rate
// limit, and the real server on loopback driven over raw sockets (what a hostile client sends)
// and through KioskLoop (an action reaches the frame source, snapshots only while watched).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <regex>

#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/log_tail.hpp"
#include "holo/kiosk/console_auth.hpp"
#include "holo/kiosk/console_server.hpp"
#include "holo/kiosk/kiosk_config.hpp"
#include "holo/kiosk/kiosk_loop.hpp"

namespace holo::kiosk {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr const char* kPassword = "correct horse battery";

std::string rawExchange(std::uint16_t port, const std::string& request) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return {};
  }
  // The server may answer (413, 431) before it has read everything: a short send is fine.
  (void)send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string response;
  char buffer[4096];
  ssize_t n;
  while ((n = recv(fd, buffer, sizeof buffer, 0)) > 0) response.append(buffer, static_cast<std::size_t>(n));
  close(fd);
  return response;
}

int statusOf(const std::string& response) {
  if (response.rfind("HTTP/1.1 ", 0) != 0) return -1;
  return std::stoi(response.substr(9, 3));
}

std::string bodyOf(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? std::string() : response.substr(end + 4);
}

std::string headerOf(const std::string& response, const std::string& name) {
  const std::regex header("\r\n" + name + ": ([^\r]*)\r\n", std::regex::icase);
  std::smatch m;
  return std::regex_search(response, m, header) ? m[1].str() : std::string();
}

struct Client {
  std::uint16_t port;
  std::string cookie;  // "holo_session=..."

  std::string get(const std::string& path, const std::string& extra = {}) const {
    return rawExchange(port, "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                 "\r\nConnection: close\r\n" +
                                 (cookie.empty() ? "" : "Cookie: " + cookie + "\r\n") + extra + "\r\n");
  }
  std::string post(const std::string& path, const std::string& body, const std::string& extra = {}) const {
    return rawExchange(port,
                       "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                           "\r\nConnection: close\r\nContent-Type: application/x-www-form-urlencoded\r\n" +
                           (cookie.empty() ? "" : "Cookie: " + cookie + "\r\n") + extra +
                           "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
  }
  // Logs in; returns the response and keeps the cookie.
  std::string login(const std::string& password) {
    const std::string response = post("/login", "password=" + password);
    const std::string set = headerOf(response, "Set-Cookie");
    if (!set.empty()) cookie = set.substr(0, set.find(';'));
    return response;
  }
  // The CSRF token the status page carries.
  std::string csrf() const {
    const std::string page = bodyOf(get("/"));
    std::smatch m;
    const std::regex meta(R"re(name="csrf-token" content="([0-9a-f]+)")re");
    return std::regex_search(page, m, meta) ? m[1].str() : std::string();
  }
};

fs::path tempDir() {
  const fs::path dir =
      fs::temp_directory_path() / ("holo_console_" + std::to_string(getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path secretFile(const fs::path& dir) {
  const fs::path file = dir / "console.secret";
  writeConsoleSecret(file, kPassword);
  return file;
}

std::string urlEncoded(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (std::isalnum(c)) {
      out += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

// A console on a free loopback port whose backend records what it is asked.
struct TestConsole {
  explicit TestConsole(const fs::path& dir)
      : auth(std::make_shared<ConsoleAuth>(readConsoleSecret(secretFile(dir)), 60min)),
        server("127.0.0.1", 0, auth,
               ConsoleBackend{[] {
                                HealthStatus h;
                                h.state = "running";
                                h.relic = "amphora";
                                return h;
                              },
                              [] {
                                return std::vector<std::string>{"line one", "line two"};
                              },
                              [this](KioskAction a) {
                                actions.push_back(a);
                                return true;
                              },
                              [this] { ++reloads; },
                              [](SnapshotKind kind, int index) {
                                return std::string(kind == SnapshotKind::Face ? "face" : "camera") +
                                       std::to_string(index);
                              }}) {}
  std::vector<KioskAction> actions;
  int reloads = 0;
  std::shared_ptr<ConsoleAuth> auth;
  ConsoleServer server;
};

TEST(ConsoleConfig, DefaultsAreOffOnLoopback) {
  const KioskConfig c = parseKioskConfig(ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"));
  EXPECT_FALSE(c.console.enabled);
  EXPECT_EQ(c.console.address, "127.0.0.1");
  EXPECT_EQ(c.console.port, 8788);
  EXPECT_EQ(c.console.secret_file, "/etc/holopyramid/console.secret");
  EXPECT_EQ(c.console.session_minutes, 60);
}

TEST(ConsoleConfig, ParsesTheSection) {
  const KioskConfig c = parseKioskConfig(
      ConfigNode::parse("kiosk:\n  console:\n    enabled: true\n    address: 0.0.0.0\n    port: 9000\n"
                        "    secret_file: /tmp/s\n    session_minutes: 15\n",
                        "x.yaml"));
  EXPECT_TRUE(c.console.enabled);
  EXPECT_EQ(c.console.address, "0.0.0.0");
  EXPECT_EQ(c.console.port, 9000);
  EXPECT_EQ(c.console.secret_file, "/tmp/s");
  EXPECT_EQ(c.console.session_minutes, 15);
}

TEST(ConsoleConfig, BadFieldsNameTheFileAndTheField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"    passwd: x\n", "kiosk.console.passwd"},
      {"    port: 70000\n", "kiosk.console.port"},
      {"    port: -1\n", "kiosk.console.port"},
      {"    address: museum.example\n", "kiosk.console.address"},
      {"    session_minutes: 0\n", "kiosk.console.session_minutes"},
      {"    session_minutes: 100000\n", "kiosk.console.session_minutes"},
      {"    secret_file: ''\n", "kiosk.console.secret_file"},
      {"    enabled: perhaps\n", "kiosk.console.enabled"},
  };
  for (const auto& [yaml, field] : cases) {
    try {
      parseKioskConfig(ConfigNode::parse("kiosk:\n  console:\n" + yaml, "museum.yaml"));
      ADD_FAILURE() << "accepted " << yaml;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "museum.yaml") << e.what();
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

TEST(ConsoleSecret, IsWrittenOwnerOnlyAndReadBack) {
  const fs::path dir = tempDir();
  const fs::path file = secretFile(dir);
  struct stat st {};
  ASSERT_EQ(stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const std::string hash = readConsoleSecret(file);
  EXPECT_EQ(hash.rfind("$argon2id$", 0), 0u) << hash;
  EXPECT_EQ(std::ifstream(file).rdbuf() != nullptr, true);
  EXPECT_EQ(fs::exists(dir / "console.secret.tmp"), false);
}

TEST(ConsoleSecret, AFileOthersCanReadIsRefusedWithTheReason) {
  const fs::path dir = tempDir();
  const fs::path file = secretFile(dir);
  for (const fs::perms perms : {fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read,
                                fs::perms::owner_read | fs::perms::others_read}) {
    fs::permissions(file, perms);
    try {
      readConsoleSecret(file);
      ADD_FAILURE() << "read a secret file of mode " << static_cast<int>(perms);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file.string());
      EXPECT_NE(std::string(e.what()).find("chmod 600"), std::string::npos) << e.what();
    }
  }
}

TEST(ConsoleSecret, MissingEmptyOrForeignFilesAreInputErrors) {
  const fs::path dir = tempDir();
  EXPECT_THROW(readConsoleSecret(dir / "none"), InputError);
  EXPECT_THROW(readConsoleSecret(dir), InputError);  // a folder
  const fs::path plain = dir / "plain";
  std::ofstream(plain) << "hunter2\n";
  fs::permissions(plain, fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_THROW(readConsoleSecret(plain), InputError);
  EXPECT_THROW(writeConsoleSecret(dir / "short", "short"), InputError);
  EXPECT_THROW(writeConsoleSecret(dir / "two", "first line is long\nsecond"), InputError);
}

TEST(ConsoleAuth, SessionsCsrfAndExpiry) {
  const fs::path dir = tempDir();
  ConsoleAuth auth(readConsoleSecret(secretFile(dir)), 10min);
  const auto t0 = ConsoleAuth::Clock::now();
  EXPECT_EQ(auth.login("10.0.0.1", "wrong password", t0).outcome, ConsoleAuth::Outcome::WrongPassword);
  const ConsoleAuth::Login login = auth.login("10.0.0.1", kPassword, t0);
  ASSERT_EQ(login.outcome, ConsoleAuth::Outcome::Ok);
  EXPECT_EQ(login.session_id.size(), 64u);
  const auto csrf = auth.csrfToken(login.session_id, t0);
  ASSERT_TRUE(csrf);
  EXPECT_EQ(csrf->size(), 64u);
  EXPECT_NE(*csrf, login.session_id);
  EXPECT_TRUE(auth.csrfMatches(login.session_id, *csrf, t0));
  EXPECT_FALSE(auth.csrfMatches(login.session_id, std::string(64, '0'), t0));
  EXPECT_FALSE(auth.csrfMatches(login.session_id, "", t0));
  EXPECT_FALSE(auth.csrfToken(std::string(64, 'a'), t0));
  EXPECT_TRUE(auth.csrfToken(login.session_id, t0 + 9min));
  EXPECT_FALSE(auth.csrfToken(login.session_id, t0 + 10min));  // expired
  const ConsoleAuth::Login again = auth.login("10.0.0.1", kPassword, t0);
  auth.logout(again.session_id);
  EXPECT_FALSE(auth.csrfToken(again.session_id, t0));
}

TEST(ConsoleAuth, RateLimitsFailuresPerClientForAMinute) {
  const fs::path dir = tempDir();
  ConsoleAuth auth(readConsoleSecret(secretFile(dir)), 10min);
  const auto t0 = ConsoleAuth::Clock::now();
  for (int i = 0; i < ConsoleAuth::kMaxFailures; ++i)
    EXPECT_EQ(auth.login("10.0.0.9", "guess", t0 + std::chrono::seconds(i)).outcome,
              ConsoleAuth::Outcome::WrongPassword);
  // Even the right password is refused now, without being checked.
  const ConsoleAuth::Login limited = auth.login("10.0.0.9", kPassword, t0 + 10s);
  EXPECT_EQ(limited.outcome, ConsoleAuth::Outcome::RateLimited);
  EXPECT_EQ(limited.retry_after_s, 50);
  // Another address is not affected; the first failure leaving the window lets one try through.
  EXPECT_EQ(auth.login("10.0.0.10", kPassword, t0 + 10s).outcome, ConsoleAuth::Outcome::Ok);
  EXPECT_EQ(auth.login("10.0.0.9", kPassword, t0 + 61s).outcome, ConsoleAuth::Outcome::Ok);
}

TEST(ConsoleAuth, KeepsAtMostMaxSessionsAndANewPasswordEndsThemAll) {
  const fs::path dir = tempDir();
  const std::string hash = readConsoleSecret(secretFile(dir));
  ConsoleAuth auth(hash, 10min);
  const auto t0 = ConsoleAuth::Clock::now();
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < ConsoleAuth::kMaxSessions + 1; ++i)
    ids.push_back(auth.login("127.0.0.1", kPassword, t0).session_id);
  EXPECT_EQ(auth.sessionCount(), ConsoleAuth::kMaxSessions);
  EXPECT_FALSE(auth.csrfToken(ids.front(), t0));
  EXPECT_TRUE(auth.csrfToken(ids.back(), t0));
  auth.setPasswordHash(hash, 5min);
  EXPECT_TRUE(auth.csrfToken(ids.back(), t0));  // same password: sessions stay
  writeConsoleSecret(dir / "other", "another password");
  auth.setPasswordHash(readConsoleSecret(dir / "other"), 5min);
  EXPECT_EQ(auth.sessionCount(), 0u);
}

TEST(ConsoleServer, WithoutASessionOnlyTheLoginPageAnswers) {
  TestConsole console(tempDir());
  Client client{console.server.port(), {}};
  const std::string page = client.get("/");
  EXPECT_EQ(statusOf(page), 200) << page;
  EXPECT_NE(bodyOf(page).find("action=\"/login\""), std::string::npos);
  EXPECT_EQ(statusOf(client.get("/console.css")), 200);
  for (const char* path : {"/api/status", "/snapshot/face/0.jpg", "/snapshot/camera/1.jpg"})
    EXPECT_EQ(statusOf(client.get(path)), 401) << path;
  for (const char* path :
       {"/api/action/next-relic", "/api/action/relearn-background", "/api/action/reload", "/logout"})
    EXPECT_EQ(statusOf(client.post(path, "")), 401) << path;
  // A made-up session is no session.
  client.cookie = "holo_session=" + std::string(64, 'f');
  EXPECT_EQ(statusOf(client.get("/api/status")), 401);
  EXPECT_TRUE(console.actions.empty());
  EXPECT_EQ(console.reloads, 0);
}

TEST(ConsoleServer, LoginGivesAStrictHttpOnlySessionAndActionsNeedItsCsrfToken) {
  TestConsole console(tempDir());
  Client client{console.server.port(), {}};
  const std::string wrong = client.login("nope");
  EXPECT_EQ(statusOf(wrong), 401) << wrong;
  EXPECT_TRUE(client.cookie.empty());
  const std::string ok = client.login(urlEncoded(kPassword));
  ASSERT_EQ(statusOf(ok), 303) << ok;
  EXPECT_EQ(headerOf(ok, "Location"), "/");
  const std::string cookie = headerOf(ok, "Set-Cookie");
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos) << cookie;
  EXPECT_EQ(headerOf(ok, "Cache-Control"), "no-store");

  const std::string status = client.get("/api/status");
  ASSERT_EQ(statusOf(status), 200) << status;
  const auto j = nlohmann::json::parse(bodyOf(status));
  EXPECT_EQ(j["health"]["relic"], "amphora");
  EXPECT_EQ(j["log"].size(), 2u);
  EXPECT_GT(j["session_s"].get<double>(), 3500.0);
  EXPECT_NE(headerOf(status, "Content-Security-Policy").find("default-src 'none'"), std::string::npos);
  const std::string jpeg = client.get("/snapshot/camera/2.jpg");
  EXPECT_EQ(statusOf(jpeg), 200);
  EXPECT_EQ(headerOf(jpeg, "Content-Type"), "image/jpeg");
  EXPECT_EQ(bodyOf(jpeg), "camera2");
  EXPECT_EQ(statusOf(client.get("/snapshot/face/4.jpg")), 404);

  const std::string csrf = client.csrf();
  ASSERT_EQ(csrf.size(), 64u);
  EXPECT_EQ(statusOf(client.post("/api/action/next-relic", "")), 403);  // no token
  EXPECT_EQ(
      statusOf(client.post("/api/action/next-relic", "", "X-CSRF-Token: " + std::string(64, '0') + "\r\n")),
      403);
  EXPECT_EQ(statusOf(client.post("/api/action/next-relic", "csrf=" + csrf.substr(1))), 403);
  // The right token from another site's page.
  EXPECT_EQ(statusOf(client.post("/api/action/next-relic", "",
                                 "X-CSRF-Token: " + csrf + "\r\nOrigin: http://evil.example\r\n")),
            403);
  EXPECT_TRUE(console.actions.empty());

  const std::string header = "X-CSRF-Token: " + csrf + "\r\n";
  EXPECT_EQ(statusOf(client.post("/api/action/next-relic", "", header)), 202);
  EXPECT_EQ(statusOf(client.post("/api/action/relearn-background", "csrf=" + csrf)), 202);
  EXPECT_EQ(
      statusOf(client.post("/api/action/reload", "",
                           header + "Origin: http://127.0.0.1:" + std::to_string(client.port) + "\r\n")),
      202);
  EXPECT_EQ(console.actions,
            (std::vector<KioskAction>{KioskAction::NextRelic, KioskAction::RelearnBackground}));
  EXPECT_EQ(console.reloads, 1);

  EXPECT_EQ(statusOf(client.post("/logout", "csrf=" + csrf)), 303);
  EXPECT_EQ(statusOf(client.get("/api/status")), 401);
}

TEST(ConsoleServer, PathTraversalIsNotFound) {
  TestConsole console(tempDir());
  Client client{console.server.port(), {}};
  client.login(urlEncoded(kPassword));
  for (const char* path : {"/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/..%2f..%2fetc%2fpasswd",
                           "/snapshot/face/../../../../etc/passwd", "/snapshot/face/..%2f..%2fetc%2fpasswd",
                           "/snapshot/face/0.jpg/../../etc/passwd", "/console.js/..%2F..%2Fetc%2Fpasswd",
                           "/%252e%252e/etc/passwd", "/snapshot/face/-1.jpg", "/snapshot/camera/16.jpg",
                           "/etc/passwd", "//etc/passwd", "/console.js%00.jpg"}) {
    const std::string response = client.get(path);
    EXPECT_EQ(statusOf(response), 404) << path << "\n" << response;
    EXPECT_EQ(bodyOf(response).find("root:"), std::string::npos) << path;
  }
}

TEST(ConsoleServer, OversizedRequestsAndOtherMethodsAreRefused) {
  TestConsole console(tempDir());
  Client client{console.server.port(), {}};
  const std::string big_body =
      client.post("/login", "password=" + std::string(ConsoleServer::kMaxBodyBytes, 'x'));
  EXPECT_EQ(statusOf(big_body), 413) << big_body.substr(0, 200);
  std::string headers;
  for (int i = 0; i < 12; ++i)
    headers += "X-Filler-" + std::to_string(i) + ": " + std::string(1000, 'y') + "\r\n";
  const std::string big_headers = client.get("/", headers);
  EXPECT_EQ(statusOf(big_headers), 431) << big_headers.substr(0, 200);
  // One header line over cpp-httplib's 8 KiB, and a request line over it: refused, not served.
  EXPECT_GE(statusOf(client.get("/", "X-Long: " + std::string(9000, 'z') + "\r\n")), 400);
  EXPECT_GE(statusOf(client.get("/" + std::string(9000, 'a'))), 400);
  for (const char* method : {"PUT", "DELETE", "OPTIONS", "TRACE", "PATCH"}) {
    const std::string response =
        rawExchange(client.port, std::string(method) + " / HTTP/1.1\r\nHost: x\r\n\r\n");
    EXPECT_EQ(statusOf(response), 405) << method;
  }
  EXPECT_TRUE(console.actions.empty());
}

TEST(ConsoleServer, RepeatedWrongPasswordsGet429) {
  TestConsole console(tempDir());
  Client client{console.server.port(), {}};
  for (int i = 0; i < ConsoleAuth::kMaxFailures; ++i)
    EXPECT_EQ(statusOf(client.login("guess" + std::to_string(i))), 401);
  const std::string limited = client.login(urlEncoded(kPassword));
  EXPECT_EQ(statusOf(limited), 429) << limited;
  EXPECT_GT(std::stoi(headerOf(limited, "Retry-After")), 0);
  EXPECT_TRUE(client.cookie.empty());
}

// KioskLoop with the console on: the test's frame source records the requests.
LoadedConfig consoleConfig(const fs::path& secret) {
  LoadedConfig c{ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"), {}, "test", {}};
  c.kiosk = parseKioskConfig(c.root);
  c.kiosk.max_fps = 240;
  c.kiosk.health_port = -1;
  c.kiosk.health_file.clear();
  c.kiosk.console.enabled = true;
  c.kiosk.console.port = 0;
  c.kiosk.console.secret_file = secret;
  return c;
}

TEST(ConsoleKioskLoop, ActionsReachTheFrameSourceOnceInOrderAndReloadTakesTheSighupPath) {
  const fs::path dir = tempDir();
  const LoadedConfig config = consoleConfig(secretFile(dir));
  std::vector<KioskAction> seen;
  int snapshots_asked = 0;
  int reloads = 0;
  KioskLoop loop(
      config,
      [&](const FrameRequest& r) {
        seen.insert(seen.end(), r.actions.begin(), r.actions.end());
        snapshots_asked += r.snapshot ? 1 : 0;
        FrameReport report;
        report.presented = true;
        return report;
      },
      [&] {
        ++reloads;
        return config;
      });
  ASSERT_NE(loop.consolePort(), 0);
  Client client{loop.consolePort(), {}};
  ASSERT_EQ(statusOf(client.login(urlEncoded(kPassword))), 303);
  const std::string header = "X-CSRF-Token: " + client.csrf() + "\r\n";
  EXPECT_EQ(statusOf(client.post("/api/action/relearn-background", "", header)), 202);
  EXPECT_EQ(statusOf(client.post("/api/action/next-relic", "", header)), 202);
  EXPECT_EQ(statusOf(client.post("/api/action/reload", "", header)), 202);
  SignalEvents signals;
  SystemdNotifier notifier;
  EXPECT_EQ(loop.run(signals, notifier, 5), 0);
  EXPECT_EQ(seen, (std::vector<KioskAction>{KioskAction::RelearnBackground, KioskAction::NextRelic}));
  EXPECT_EQ(reloads, 1);
  EXPECT_EQ(snapshots_asked, 0);  // nobody watched
}

TEST(ConsoleKioskLoop, SnapshotsAreTakenOnlyWhileWatchedAndServedAsJpeg) {
  const fs::path dir = tempDir();
  const LoadedConfig config = consoleConfig(secretFile(dir));
  int snapshots_asked = 0;
  KioskLoop loop(
      config,
      [&](const FrameRequest& r) {
        FrameReport report;
        report.presented = true;
        if (r.snapshot) {
          ++snapshots_asked;
          report.snapshot.emplace();
          for (cv::Mat& face : report.snapshot->faces)
            face = cv::Mat(32, 32, CV_8UC3, cv::Scalar(0, 80, 200));
          report.snapshot->cameras = {cv::Mat(720, 1280, CV_8UC3, cv::Scalar(50, 50, 50))};
        }
        return report;
      },
      [&] { return config; });
  EXPECT_TRUE(loop.snapshotJpeg(SnapshotKind::Face, 0).empty());  // none yet; now it is wanted
  SignalEvents signals;
  SystemdNotifier notifier;
  const auto start = std::chrono::steady_clock::now();
  loop.run(signals, notifier, 20);
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(snapshots_asked, 1);
  EXPECT_LE(snapshots_asked, 1 + static_cast<int>(elapsed_s * KioskLoop::kSnapshotsPerSecond));
  const std::string face = loop.snapshotJpeg(SnapshotKind::Face, 3);
  ASSERT_GT(face.size(), 4u);
  EXPECT_EQ(static_cast<unsigned char>(face[0]), 0xFF);
  EXPECT_EQ(static_cast<unsigned char>(face[1]), 0xD8);
  EXPECT_FALSE(loop.snapshotJpeg(SnapshotKind::Camera, 0).empty());
  EXPECT_TRUE(loop.snapshotJpeg(SnapshotKind::Camera, 1).empty());
}

TEST(ConsoleKioskLoop, ASecretFileOthersCanReadKeepsTheConsoleOffAndSaysWhy) {
  const fs::path dir = tempDir();
  const fs::path secret = secretFile(dir);
  fs::permissions(secret, fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_read);
  KioskLoop loop(
      consoleConfig(secret), [](const FrameRequest&) { return FrameReport{}; },
      [&] { return consoleConfig(secret); });
  EXPECT_EQ(loop.consolePort(), 0);
  bool reported = false;
  for (const auto& e : loop.health().last_errors)
    reported |=
        e.find("console not started") != std::string::npos && e.find("chmod 600") != std::string::npos;
  EXPECT_TRUE(reported);
}

TEST(LogTail, KeepsTheNewestLines) {
  HOLO_LOG_INFO("console log tail test {}", 1);
  HOLO_LOG_WARN("console log tail test {}", 2);
  const auto tail = logTail(2);
  ASSERT_EQ(tail.size(), 2u);
  EXPECT_NE(tail[0].find("info console log tail test 1"), std::string::npos) << tail[0];
  EXPECT_NE(tail[1].find("warning console log tail test 2"), std::string::npos) << tail[1];
  EXPECT_TRUE(logTail(0).empty());
}

}  // namespace
}  // namespace holo::kiosk
