// The technician's console: raw request bytes through cpp-httplib's request handling and the
// console's routes (login, session cookie, CSRF token, actions, snapshots, the limits), without a
// socket. A session exists before each input: the literal text @SESSION@ and @CSRF@ in the input
// become its id and CSRF token, so mutations reach the routes behind the login too. The server
// must answer every request with a status line, and act only on requests that carry both.
#include <httplib.h>
#include <sodium.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "holo/core/log.hpp"
#include "holo/kiosk/console_auth.hpp"
#include "holo/kiosk/console_server.hpp"

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
    port = 8788;
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

constexpr const char* kPassword = "fuzzing password";

// The hash at libsodium's minimum cost: a wrong password in an input costs microseconds, not the
// 0.1 s of the product's interactive limits.
std::string cheapHash() {
  holo::initLogging(holo::LogLevel::Off);  // every login and refusal is logged: millions of lines
  if (sodium_init() < 0) __builtin_trap();
  char hash[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str_alg(hash, kPassword, std::strlen(kPassword), crypto_pwhash_OPSLIMIT_MIN,
                            crypto_pwhash_MEMLIMIT_MIN, crypto_pwhash_ALG_ARGON2ID13) != 0)
    __builtin_trap();
  return hash;
}

void replaceAll(std::string& text, const std::string& marker, const std::string& value) {
  for (std::size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + value.size()))
    text.replace(at, marker.size(), value);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string hash = cheapHash();
  auto auth = std::make_shared<holo::kiosk::ConsoleAuth>(hash, std::chrono::minutes(5));
  const auto login = auth->login("127.0.0.1", kPassword);
  if (login.outcome != holo::kiosk::ConsoleAuth::Outcome::Ok) __builtin_trap();
  const std::string csrf = *auth->csrfToken(login.session_id);

  std::string input(reinterpret_cast<const char*>(data), size);
  replaceAll(input, "@SESSION@", login.session_id);
  replaceAll(input, "@CSRF@", csrf);

  int acted = 0;
  BytesServer server;
  holo::kiosk::addConsoleRoutes(
      server, auth,
      holo::kiosk::ConsoleBackend{
          [] { return holo::kiosk::HealthStatus{}; }, [] { return std::vector<std::string>{"a log line"}; },
          [&](holo::kiosk::KioskAction) {
            ++acted;
            return true;
          },
          [&] { ++acted; }, [](holo::kiosk::SnapshotKind, int) { return std::string("\xFF\xD8jpeg"); }});
  const std::string response = server.answer(input);
  if (!response.empty() && response.rfind("HTTP/1.1 ", 0) != 0) __builtin_trap();
  // An action needs the session and its token somewhere in the request.
  if (acted > 0 &&
      (input.find(login.session_id) == std::string::npos || input.find(csrf) == std::string::npos))
    __builtin_trap();
  return 0;
}
