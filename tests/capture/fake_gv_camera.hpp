// Test fixtures for Aravis: a network namespace of the test's own (so fake cameras get addresses
// of their own and nothing touches the host's network) and fake GigE Vision cameras
// (arv-fake-gv-camera-0.8 from aravis-tools) started in it and stopped by PID.
#pragma once

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace holo::test {

inline std::string findProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const auto candidate = std::filesystem::path(dir) / name;
    if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return {};
}

// Runs a program with arguments, output to `log` (or /dev/null); returns its PID or -1.
inline pid_t spawn(const std::vector<std::string>& args, const std::string& log = "/dev/null") {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

inline int runAndWait(const std::vector<std::string>& args) {
  const pid_t pid = spawn(args);
  if (pid < 0) return -1;
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs a program with output to `log`, killing it when it outlives `limit`; returns its exit
// code, or -1 when it could not start, died from a signal or was killed.
inline int runWithTimeout(const std::vector<std::string>& args, const std::string& log,
                          std::chrono::milliseconds limit) {
  const pid_t pid = spawn(args, log);
  if (pid < 0) return -1;
  const auto end = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A network namespace with loopback up and extra loopback addresses. enter() moves the calling
// thread (and every thread it creates afterwards: Aravis's stream threads, capture threads)
// into it; leave() moves it back.
class NetworkNamespace {
 public:
  explicit NetworkNamespace(std::string name) : name_(std::move(name)) {}
  ~NetworkNamespace() {
    leave();
    if (created_) runAndWait({"ip", "netns", "del", name_});
  }

  // Returns "" on success, else why it is not possible here.
  std::string create(const std::vector<std::string>& addresses) {
    if (::geteuid() != 0) return "network namespaces need root";
    if (findProgram("ip").empty()) return "the ip program (iproute2) is not installed";
    runAndWait({"ip", "netns", "del", name_});  // a leftover from a crashed run
    if (runAndWait({"ip", "netns", "add", name_}) != 0)
      return "ip netns add " + name_ + " failed (not allowed here)";
    created_ = true;
    if (runAndWait({"ip", "netns", "exec", name_, "ip", "link", "set", "lo", "up"}) != 0)
      return "cannot bring up loopback in " + name_;
    for (const auto& a : addresses)
      if (runAndWait({"ip", "netns", "exec", name_, "ip", "addr", "add", a + "/8", "dev", "lo"}) != 0)
        return "cannot add address " + a;
    return {};
  }

  bool enter() {
    original_ = ::open("/proc/self/ns/net", O_RDONLY);
    const int fd = ::open(("/run/netns/" + name_).c_str(), O_RDONLY);
    const bool ok = original_ >= 0 && fd >= 0 && ::setns(fd, CLONE_NEWNET) == 0;
    if (fd >= 0) ::close(fd);
    return ok;
  }
  void leave() {
    if (original_ < 0) return;
    ::setns(original_, CLONE_NEWNET);
    ::close(original_);
    original_ = -1;
  }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  bool created_ = false;
  int original_ = -1;
};

// One arv-fake-gv-camera-0.8 process inside a namespace.
class FakeCamera {
 public:
  FakeCamera(std::string netns, std::string address, std::string serial, int lost_per_thousand = 0)
      : netns_(std::move(netns)),
        address_(std::move(address)),
        serial_(std::move(serial)),
        loss_(lost_per_thousand) {}
  ~FakeCamera() { kill(); }
  FakeCamera(const FakeCamera&) = delete;
  FakeCamera& operator=(const FakeCamera&) = delete;

  bool start() {
    std::vector<std::string> args{"ip", "netns",  "exec", netns_, "arv-fake-gv-camera-0.8",
                                  "-i", address_, "-s",   serial_};
    if (loss_ > 0) args.insert(args.end(), {"-r", std::to_string(loss_)});
    pid_ = spawn(args);  // `ip netns exec` execs the camera: the PID is the camera's
    return pid_ > 0;
  }
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);  // like pulling the cable: no goodbye packets
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  pid_t pid() const { return pid_; }
  const std::string& serial() const { return serial_; }

 private:
  std::string netns_, address_, serial_;
  int loss_;
  pid_t pid_ = -1;
};

}  // namespace holo::test
