// Who may use the technician's console (console_server.hpp): one password, kept only as its
// argon2id hash (libsodium's crypto_pwhash_str format) in a secret file nobody but its owner can
// read; sessions that last a fixed time from the login; one CSRF token per session; a login
// rate limit per client address.
//
// Invariants: session ids and CSRF tokens are 32 random bytes (randombytes_buf) as 64 hex
// digits; they and the password are compared in constant time; at most kMaxSessions sessions
// live at once (a new login ends the oldest); at most kMaxFailures failed logins per client
// address within kFailureWindow, further attempts are refused without checking the password;
// one password check runs at a time (each takes argon2id's 64 MiB and ~0.1 s, so a flood of
// logins from many addresses costs neither memory nor all cores). Thread-safe.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace holo::kiosk {

inline constexpr std::size_t kMinPasswordLength = 10;

// The secret file's hash. Throws InputError naming the file when it is missing or unreadable, not
// a regular file, readable or writable by its group or others (it must be mode 0600 or 0400), or
// holds no argon2id hash.
std::string readConsoleSecret(const std::filesystem::path& path);
// Hashes `password` (argon2id at libsodium's interactive limits) and writes the hash to `path`
// atomically with mode 0600. Throws InputError when the password is shorter than
// kMinPasswordLength characters or holds a line break, holo::Error when the file cannot be written.
void writeConsoleSecret(const std::filesystem::path& path, const std::string& password);

class ConsoleAuth {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kMaxFailures = 5;
  static constexpr std::chrono::seconds kFailureWindow{60};
  static constexpr std::size_t kMaxSessions = 16;
  static constexpr std::size_t kMaxClientsTracked = 4096;

  // `password_hash` as readConsoleSecret returns it.
  ConsoleAuth(std::string password_hash, std::chrono::minutes session_length);

  enum class Outcome { Ok, WrongPassword, RateLimited };
  struct Login {
    Outcome outcome = Outcome::WrongPassword;
    std::string session_id;  // Ok only
    int retry_after_s = 0;   // RateLimited only: when the client may try again
  };
  Login login(const std::string& client, const std::string& password, Clock::time_point now = Clock::now());

  // The session's CSRF token, none when `session_id` names no live session.
  std::optional<std::string> csrfToken(const std::string& session_id, Clock::time_point now = Clock::now());
  // True when `session_id` is live and `token` is its CSRF token.
  bool csrfMatches(const std::string& session_id, const std::string& token,
                   Clock::time_point now = Clock::now());
  // Seconds the session has left (0 when none).
  double secondsLeft(const std::string& session_id, Clock::time_point now = Clock::now());
  void logout(const std::string& session_id);

  // A new password hash (reload): every session ends when it differs from the old one.
  void setPasswordHash(std::string password_hash, std::chrono::minutes session_length);
  std::size_t sessionCount() const;

 private:
  struct Session {
    std::string id;
    std::string csrf;
    Clock::time_point expires;
  };
  Session* find(const std::string& session_id, Clock::time_point now);  // expects mutex_

  mutable std::mutex mutex_;  // guards everything below but the password check
  std::mutex verify_mutex_;   // one argon2id check at a time
  std::string hash_;
  std::chrono::minutes session_length_;
  std::vector<Session> sessions_;                                   // oldest first
  std::map<std::string, std::vector<Clock::time_point>> failures_;  // per client, in the window
};

}  // namespace holo::kiosk
