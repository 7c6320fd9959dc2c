// Runs the real `holopyramid kiosk --headless` as systemd would: with a NOTIFY_SOCKET that the
// test owns (an AF_UNIX datagram socket) and WATCHDOG_USEC, and records what the kiosk says.
// Faults are switched on and off through the kiosk's test fault file (fault_injector.hpp).
#pragma once
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

#include <functional>

#include "holo/core/files.hpp"
#include "shared_data.hpp"

namespace holo::test {

using Clock = std::chrono::steady_clock;

struct Message {
  double t;  // seconds since the kiosk started
  std::string text;
};

class KioskProcess {
 public:
  // `env` entries are "NAME=value" added to the kiosk's environment.
  // `args` are added to the kiosk's command line (--scene, --view-size for the pipeline).
  KioskProcess(const std::string& name, const std::string& config_text, const std::string& faults = {},
               std::vector<std::string> env = {}, long watchdog_usec = 1'000'000,
               std::string source = "test-pattern", std::vector<std::string> args = {})
      : dir_(holo::test::scratchDir("kiosk_process_" + name)), source_(std::move(source)) {
    holo::writeFileAtomically(dir_ / "site.yaml", config_text);
    setFaults(faults);
    env.push_back("HOLO_KIOSK_TEST_FAULTS=" + (dir_ / "faults.txt").string());
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
      std::vector<std::string> argv = {
          HOLO_APP_BINARY, "kiosk", "--headless",    "--source", source_,         "--config", config,
          "--state-dir",   state,   "--health-port", "0",        "--health-file", health};
      argv.insert(argv.end(), args.begin(), args.end());
      std::vector<char*> pointers;
      for (auto& a : argv) pointers.push_back(a.data());
      pointers.push_back(nullptr);
      execv(HOLO_APP_BINARY, pointers.data());
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

  // Collects messages until `until` returns true for the latest one, or `timeout` passes. A test
  // waiting for anything else waits here, as systemd keeps reading: the kiosk's sd_notify blocks
  // once the socket's queue is full, and its frames stop with it.
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
  void setFaults(const std::string& faults) const { holo::writeFileAtomically(dir_ / "faults.txt", faults); }
  pid_t pid() const { return pid_; }
  // True while the process has not exited (reaps it when it has).
  bool alive() {
    if (exited_) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) exited_ = true;
    return !exited_;
  }
  // Resident memory in kB (VmRSS), 0 when unreadable.
  long rssKb() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return 0;
  }
  // Exit code, or -1 when it did not exit within `timeout`.
  int wait(std::chrono::duration<double> timeout) {
    const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
    while (Clock::now() < end) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      readUntil(std::chrono::milliseconds(50));
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
  std::string source_;  // --source of the kiosk: test-pattern (cheap) or pipeline
  int fd_ = -1;
  pid_t pid_ = -1;
  bool exited_ = false;
  Clock::time_point started_;
};

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

// The simulated museum with small, slow cameras (160x90 at 10 fps): the whole live pipeline,
// cheap enough for a 2-core CI machine. Returns the --scene/--view-size arguments for the kiosk.
inline std::vector<std::string> smallMuseumArgs(const std::string& name, int view_size = 96) {
  const auto scene = holo::test::scratchDir("kiosk_scene_" + name) / "small_museum.yaml";
  holo::writeFileAtomically(scene, "base: museum\ncamera: {width: 160, height: 90, fps: 10}\n");
  return {"--scene", scene.string(), "--view-size", std::to_string(view_size)};
}

// The body of a /health response as JSON (throws when it does not parse).
inline nlohmann::json healthJson(int port) {
  const std::string response = httpGet(port, "/health");
  const auto body = response.find("\r\n\r\n");
  return nlohmann::json::parse(response.substr(body == std::string::npos ? 0 : body + 4));
}

}  // namespace holo::test
