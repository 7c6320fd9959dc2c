// The health endpoint: raw request bytes through cpp-httplib's request handling and our routes
// (/health JSON, /metrics Prometheus text, the method and body limits), without a socket. The
// first input line names a camera and a stage, so label escaping sees arbitrary text too. The
// server must answer every request with a status line and never serve a body that breaks the
// Prometheus line format or is not UTF-8, whatever bytes the names hold.
#include <httplib.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "holo/kiosk/health_server.hpp"
#include "holo/kiosk/health_status.hpp"

namespace {

class BytesStream : public httplib::Stream {
 public:
  explicit BytesStream(std::string_view input) : input_(input) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, input_.size());
    std::copy_n(input_.data(), n, ptr);
    input_.remove_prefix(n);
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    output.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 40000;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 8787;
  }
  socket_t socket() const override { return 0; }
  std::string output;

 private:
  std::string_view input_;
};

class BytesServer : public httplib::Server {
 public:
  std::string answer(std::string_view request) {
    BytesStream stream(request);
    bool closed = false;
    process_request(stream, true, closed, nullptr);
    return stream.output;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view input(reinterpret_cast<const char*>(data), size);
  const auto newline = input.find('\n');
  const std::string name(input.substr(0, std::min(newline, input.size())));
  if (newline != std::string_view::npos) input.remove_prefix(newline + 1);

  holo::kiosk::HealthStatus status;
  status.cameras = {{name, true, 7, 1, 0, 0.03}};
  status.stage_ms = {{name, 2.5}};
  status.state = name;
  BytesServer server;
  holo::kiosk::addHealthRoutes(
      server, [&] { return status; }, std::make_shared<std::atomic<long>>(0));
  const std::string response = server.answer(input);
  if (!response.empty() && response.rfind("HTTP/1.1 ", 0) != 0) __builtin_trap();

  // Every sample line stays one line whatever the names hold: no label value breaks out. The
  // same status with a plain name gives the number of sample lines to expect.
  const std::string metrics = status.toPrometheus();
  const auto countSamples = [](const std::string& text) -> long {
    long samples = 0;
    for (std::size_t start = 0; start < text.size();) {
      const std::size_t end = text.find('\n', start);
      const std::string_view line(text.data() + start, end - start);
      if (line.rfind("holopyramid_", 0) == 0)
        ++samples;
      else if (line.rfind("# ", 0) != 0)
        return -1;
      start = end + 1;
    }
    return samples;
  };
  holo::kiosk::HealthStatus plain = status;
  plain.cameras.front().name = plain.state = "camera";
  plain.stage_ms = {{"stage", 2.5}};
  const long expected = countSamples(plain.toPrometheus());
  if (expected <= 0 || countSamples(metrics) != expected) __builtin_trap();
  // Both documents are UTF-8: nlohmann's dump() throws (an uncaught exception is a finding) on
  // a string that is not, so it checks /metrics and is what /health and the health file use.
  (void)nlohmann::json(metrics).dump();
  (void)status.toJson().dump();
  return 0;
}
