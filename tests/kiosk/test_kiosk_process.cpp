// Runs the real `holopyramid kiosk --headless` as systemd would: with a NOTIFY_SOCKET that this
// test owns (an AF_UNIX datagram socket) and WATCHDOG_USEC, then reads what the kiosk says.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "holo/core/files.hpp"
#include "shared_data.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

struct Message {
  double t;  // seconds since the kiosk started
  std::string text;
};

class KioskProcess {
 public:
  // `env` entries are "NAME=value" added to the kiosk's environment.
  KioskProcess(const std::string& name, const std::string& config_text, std::vector<std::string> env = {},
               long watchdog_usec = 1'000'000)
      : dir_(holo::test::scratchDir("kiosk_process_" + name)) {
    holo::writeFileAtomically(dir_ / "site.yaml", config_text);
    socket_path_ = (dir_ / "notify.sock").string();
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", socket_path_.c_str());
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      throw std::runtime_error("bind notify socket");
    env.push_back("NOTIFY_SOCKET=" + socket_path_);
    if (watchdog_usec > 0) env.push_back("WATCHDOG_USEC=" + std::to_string(watchdog_usec));
    started_ = Clock::now();
    pid_ = fork();
    if (pid_ == 0) {
      const std::string log = (dir_ / "kiosk.log").string();
      const int out = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(out, 1);
      dup2(out, 2);
      unsetenv("WATCHDOG_PID");
      for (auto& e : env) putenv(e.data());
      const std::string config = (dir_ / "site.yaml").string();
      const std::string state = (dir_ / "state").string();
      const std::string health = (dir_ / "health.json").string();
      execl(HOLO_APP_BINARY, HOLO_APP_BINARY, "kiosk", "--headless", "--config", config.c_str(),
            "--state-dir", state.c_str(), "--health-port", "0", "--health-file", health.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~KioskProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(fd_);
  }

  // Collects messages until `until` returns true for the latest one, or `timeout` passes.
  bool readUntil(std::chrono::duration<double> timeout,
                 const std::function<bool(const Message&)>& until = {}) {
    const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
    char buffer[4096];
    while (Clock::now() < end) {
      pollfd pfd{fd_, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
      if (poll(&pfd, 1, static_cast<int>(std::max<long>(1, left.count()))) <= 0) continue;
      const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) continue;
      messages.push_back({std::chrono::duration<double>(Clock::now() - started_).count(),
                          std::string(buffer, static_cast<std::size_t>(n))});
      if (until && until(messages.back())) return true;
    }
    return false;
  }
  bool readUntilContains(const std::string& text, std::chrono::duration<double> timeout) {
    return readUntil(timeout, [&](const Message& m) { return m.text.find(text) != std::string::npos; });
  }
  // Times of the messages containing `text` in [from, to) seconds.
  std::vector<double> times(const std::string& text, double from = 0, double to = 1e9) const {
    std::vector<double> out;
    for (const auto& m : messages)
      if (m.t >= from && m.t < to && m.text.find(text) != std::string::npos) out.push_back(m.t);
    return out;
  }
  void signal(int sig) const { kill(pid_, sig); }
  // Exit code, or -1 when it did not exit within `timeout`.
  int wait(std::chrono::duration<double> timeout) {
    const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
    while (Clock::now() < end) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      readUntil(50ms);
    }
    return -1;
  }
  std::string log() const {
    std::ifstream in(dir_ / "kiosk.log");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  int healthPort() const {
    std::smatch m;
    const std::string text = log();
    static const std::regex re("health endpoint on http://127\\.0\\.0\\.1:([0-9]+)/health");
    return std::regex_search(text, m, re) ? std::stoi(m[1]) : 0;
  }
  const std::filesystem::path& dir() const { return dir_; }
  std::vector<Message> messages;

 private:
  std::filesystem::path dir_;
  std::string socket_path_;
  int fd_ = -1;
  pid_t pid_ = -1;
  bool exited_ = false;
  Clock::time_point started_;
};

const char* kConfig = R"(kiosk:
  max_fps: 20
  status_interval_s: 0.2
  degradation: {frame_budget_ms: 1000}
display:
  output_size: [256, 256]
)";

std::string httpGet(int port, const std::string& path) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  std::string response;
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + path + " HTTP/1.0\r\n\r\n";
    if (send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size())) {
      char buffer[4096];
      ssize_t n;
      while ((n = recv(fd, buffer, sizeof buffer, 0)) > 0)
        response.append(buffer, static_cast<std::size_t>(n));
    }
  }
  close(fd);
  return response;
}

TEST(KioskProcess, NotifiesReadyWatchdogStatusReloadAndStop) {
  KioskProcess kiosk("lifecycle", kConfig);
  ASSERT_TRUE(kiosk.readUntilContains("READY=1", 30s)) << kiosk.log();
  const double ready_at = kiosk.times("READY=1").front();
  // The READY message carries the first status line.
  EXPECT_NE(kiosk.messages.back().text.find("STATUS=cameras 0/0"), std::string::npos)
      << kiosk.messages.back().text;

  // Three seconds of running: WATCHDOG=1 every 0.5 s (WATCHDOG_USEC = 1 s, petted at half).
  kiosk.readUntil(3s);
  const auto pets = kiosk.times("WATCHDOG=1", ready_at, ready_at + 3.0);
  EXPECT_GE(pets.size(), 4u) << kiosk.log();
  EXPECT_LE(pets.size(), 8u);
  for (std::size_t i = 1; i < pets.size(); ++i) {
    EXPECT_GE(pets[i] - pets[i - 1], 0.45);
    EXPECT_LE(pets[i] - pets[i - 1], 0.9);
  }
  const auto statuses = kiosk.times("STATUS=");
  ASSERT_FALSE(statuses.empty());
  bool saw_fps = false;
  for (const auto& m : kiosk.messages) {
    if (m.text.rfind("STATUS=", 0) != 0) continue;
    EXPECT_NE(m.text.find("mode ibl-only"), std::string::npos) << m.text;
    if (std::regex_search(m.text, std::regex("[1-9][0-9]*\\.[0-9] fps"))) saw_fps = true;
  }
  EXPECT_TRUE(saw_fps) << "no STATUS with a non-zero frame rate";

  // The health endpoint answers with valid JSON.
  const int port = kiosk.healthPort();
  ASSERT_GT(port, 0) << kiosk.log();
  const std::string response = httpGet(port, "/health");
  ASSERT_EQ(response.rfind("HTTP/1.0 200 OK", 0), 0u) << response;
  const auto health = nlohmann::json::parse(response.substr(response.find("\r\n\r\n") + 4));
  EXPECT_EQ(health["state"], "running");
  EXPECT_GT(health["frames"].get<int>(), 10);
  EXPECT_GT(health["stage_ms"]["present"].get<double>(), 0.0);
  EXPECT_EQ(health["config"]["warning"], "");
  // And the file was written atomically next to it.
  const auto file = nlohmann::json::parse(holo::readFile(kiosk.dir() / "health.json"));
  EXPECT_GT(file["frames"].get<int>(), 0);

  // SIGHUP: RELOADING=1 then READY=1 again.
  const std::size_t before = kiosk.messages.size();
  kiosk.signal(SIGHUP);
  ASSERT_TRUE(kiosk.readUntilContains("RELOADING=1", 10s)) << kiosk.log();
  ASSERT_TRUE(kiosk.readUntilContains("READY=1", 10s)) << kiosk.log();
  EXPECT_GT(kiosk.messages.size(), before);

  // SIGTERM: STOPPING=1 and exit 0.
  kiosk.signal(SIGTERM);
  EXPECT_EQ(kiosk.wait(15s), 0) << kiosk.log();
  EXPECT_FALSE(kiosk.times("STOPPING=1").empty());
  EXPECT_EQ(nlohmann::json::parse(holo::readFile(kiosk.dir() / "health.json"))["state"], "stopping");
}

TEST(KioskProcess, AFrozenFrameLoopStopsTheWatchdogPings) {
  // Frame 30 hangs for 4 s (1.5 s at 20 fps after start), then the loop resumes.
  KioskProcess kiosk("frozen", kConfig, {"HOLO_KIOSK_TEST_FREEZE=30:4"});
  ASSERT_TRUE(kiosk.readUntilContains("READY=1", 30s)) << kiosk.log();
  kiosk.readUntil(8s);
  kiosk.signal(SIGTERM);
  EXPECT_EQ(kiosk.wait(15s), 0) << kiosk.log();
  // The longest gap between pings is the hang (about 4 s); before and after, 0.5 s.
  const auto pets = kiosk.times("WATCHDOG=1");
  ASSERT_GE(pets.size(), 4u) << kiosk.log();
  double longest = 0;
  int long_gaps = 0;
  for (std::size_t i = 1; i < pets.size(); ++i) {
    const double gap = pets[i] - pets[i - 1];
    longest = std::max(longest, gap);
    long_gaps += gap > 1.5 ? 1 : 0;
  }
  EXPECT_GE(longest, 3.5) << "pings continued through the hang";
  EXPECT_LE(longest, 5.5);
  EXPECT_EQ(long_gaps, 1);
  // And they resumed after it.
  EXPECT_GE(pets.back() - pets.front(), longest + 1.0);
}

TEST(KioskProcess, CorruptConfigStartsWithDefaultsAndSaysSo) {
  KioskProcess kiosk("corrupt", "kiosk: {max_fps: [oops\n");
  ASSERT_TRUE(kiosk.readUntilContains("READY=1", 30s)) << kiosk.log();
  const std::string ready = kiosk.messages.back().text;
  EXPECT_NE(ready.find("CONFIG: using factory defaults"), std::string::npos) << ready;
  EXPECT_NE(ready.find("site.yaml"), std::string::npos) << ready;
  kiosk.signal(SIGTERM);
  EXPECT_EQ(kiosk.wait(15s), 0) << kiosk.log();
  const auto health = nlohmann::json::parse(holo::readFile(kiosk.dir() / "health.json"));
  EXPECT_EQ(health["config"]["source"], "factory defaults");
}

TEST(KioskProcess, OverloadLowersTheQualityAndTheHealthShowsIt) {
  // 120 ms extra per frame at full quality against an 80 ms budget: the kiosk must step down
  // (to "reduced", where the extra is 60 ms, or further on a loaded machine).
  const char* config = R"(kiosk:
  max_fps: 30
  status_interval_s: 0.2
  degradation: {frame_budget_ms: 80, down_after_frames: 3, cooldown_frames: 3, up_after_frames: 1000}
display:
  output_size: [256, 256]
)";
  KioskProcess kiosk("overload", config, {"HOLO_KIOSK_TEST_FRAME_MS=120"});
  ASSERT_TRUE(kiosk.readUntil(30s, [](const Message& m) {
    return m.text.find("STATUS=") != std::string::npos && m.text.find("quality full") == std::string::npos;
  })) << kiosk.log();
  kiosk.signal(SIGTERM);
  EXPECT_EQ(kiosk.wait(15s), 0) << kiosk.log();
  const auto health = nlohmann::json::parse(holo::readFile(kiosk.dir() / "health.json"));
  bool reported = false;
  for (const auto& e : health["last_errors"])
    reported |= e.get<std::string>().find("quality stepped to 'reduced'") != std::string::npos;
  EXPECT_TRUE(reported) << health.dump(2);
}

TEST(KioskProcess, OutsideOpeningHoursTheKioskBlanksAndStaysAlive) {
  // No opening at all this week except a minute that has passed or will come: "Mon 00:00-00:01"
  // is closed almost always; the kiosk must still pet the watchdog with black frames.
  KioskProcess kiosk("closed", R"(kiosk: {opening_hours: "Mon 00:00-00:01", status_interval_s: 0.2}
display: {output_size: [128, 128]}
)");
  ASSERT_TRUE(kiosk.readUntilContains("READY=1", 30s)) << kiosk.log();
  const double ready_at = kiosk.times("READY=1").front();
  kiosk.readUntil(2.5s);
  EXPECT_GE(kiosk.times("WATCHDOG=1", ready_at).size(), 3u) << kiosk.log();
  EXPECT_FALSE(kiosk.times("blanked").empty());
  kiosk.signal(SIGTERM);
  EXPECT_EQ(kiosk.wait(15s), 0) << kiosk.log();
}

}  // namespace
