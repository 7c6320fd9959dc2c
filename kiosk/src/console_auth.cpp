#include "holo/kiosk/console_auth.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "holo/core/error.hpp"

namespace holo::kiosk {
namespace {

void initSodium() {
  if (sodium_init() < 0) throw Error("libsodium could not be initialised");
}

std::string randomToken() {
  unsigned char bytes[32];
  randombytes_buf(bytes, sizeof bytes);
  char hex[2 * sizeof bytes + 1];
  sodium_bin2hex(hex, sizeof hex, bytes, sizeof bytes);
  return hex;
}

bool equalConstantTime(const std::string& a, const std::string& b) {
  return a.size() == b.size() && sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

std::string octal(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

}  // namespace

std::string readConsoleSecret(const std::filesystem::path& path) {
  initSodium();
  const std::string file = path.string();
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0)
    throw InputError(file, "",
                     "the console's password hash file (make it with `holopyramid console-password`)",
                     std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw InputError(file, "", "a regular file holding the console's password hash");
  if ((st.st_mode & 077) != 0)
    throw InputError(file, "",
                     "a file only its owner can read (mode 0600 or 0400); the console does not start "
                     "while others can read its password hash: chmod 600 " +
                         file,
                     "mode " + octal(st.st_mode));
  std::ifstream in(path);
  std::string hash;
  if (!in || !std::getline(in, hash))
    throw InputError(file, "", "a readable file holding the console's password hash", std::strerror(errno));
  while (!hash.empty() && (hash.back() == '\r' || hash.back() == ' ')) hash.pop_back();
  if (hash.rfind(crypto_pwhash_argon2id_STRPREFIX, 0) != 0 || hash.size() >= crypto_pwhash_STRBYTES)
    throw InputError(file, "", "an argon2id hash as `holopyramid console-password` writes it",
                     hash.empty() ? "an empty line" : "something else");
  return hash;
}

void writeConsoleSecret(const std::filesystem::path& path, const std::string& password) {
  initSodium();
  if (password.size() < kMinPasswordLength)
    throw InputError("", "password", "at least " + std::to_string(kMinPasswordLength) + " characters",
                     std::to_string(password.size()) + " characters");
  if (password.find_first_of("\r\n") != std::string::npos)
    throw InputError("", "password", "one line", "a line break");
  char hash[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str_alg(hash, password.data(), password.size(), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                            crypto_pwhash_MEMLIMIT_INTERACTIVE, crypto_pwhash_ALG_ARGON2ID13) != 0)
    throw Error("console password: out of memory while hashing");
  // Written beside the target with mode 0600 from the start, then renamed over it: the hash is
  // never readable by others, not even for a moment, and a crash leaves the old file.
  const std::filesystem::path tmp = path.string() + ".tmp";
  const std::string text = std::string(hash) + "\n";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) throw Error("cannot write " + tmp.string() + ": " + std::strerror(errno));
  const bool ok = ::fchmod(fd, 0600) == 0 &&
                  ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
                  ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!ok || ::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = ok ? errno : saved;
    ::unlink(tmp.c_str());
    throw Error("cannot write " + path.string() + ": " + std::strerror(err));
  }
}

ConsoleAuth::ConsoleAuth(std::string password_hash, std::chrono::minutes session_length)
    : hash_(std::move(password_hash)), session_length_(session_length) {
  initSodium();
}

ConsoleAuth::Login ConsoleAuth::login(const std::string& client, const std::string& password,
                                      Clock::time_point now) {
  std::string hash;
  {
    std::lock_guard lock(mutex_);
    // Looked up, not inserted: only a failed check (at most one per argon2id run) adds a client.
    if (const auto found = failures_.find(client); found != failures_.end()) {
      auto& times = found->second;
      std::erase_if(times, [&](Clock::time_point t) { return now - t >= kFailureWindow; });
      if (static_cast<int>(times.size()) >= kMaxFailures) {
        const auto wait = std::chrono::ceil<std::chrono::seconds>(times.front() + kFailureWindow - now);
        return {Outcome::RateLimited, {}, static_cast<int>(std::max<long>(1, wait.count()))};
      }
    }
    hash = hash_;
  }
  bool ok = false;
  {
    std::lock_guard verify(verify_mutex_);
    ok = crypto_pwhash_str_verify(hash.c_str(), password.data(), password.size()) == 0;
  }
  std::lock_guard lock(mutex_);
  if (!ok) {
    if (failures_.size() > kMaxClientsTracked) {  // forget the clients whose failures expired
      std::erase_if(failures_, [&](const auto& entry) {
        return entry.second.empty() || now - entry.second.back() >= kFailureWindow;
      });
    }
    failures_[client].push_back(now);
    return {Outcome::WrongPassword, {}, 0};
  }
  failures_.erase(client);
  std::erase_if(sessions_, [&](const Session& s) { return s.expires <= now; });
  if (sessions_.size() >= kMaxSessions) sessions_.erase(sessions_.begin());
  sessions_.push_back({randomToken(), randomToken(), now + session_length_});
  return {Outcome::Ok, sessions_.back().id, 0};
}

ConsoleAuth::Session* ConsoleAuth::find(const std::string& session_id, Clock::time_point now) {
  // Every session is compared, so the time taken says nothing about which ids exist.
  Session* found = nullptr;
  for (Session& s : sessions_)
    if (equalConstantTime(s.id, session_id) && s.expires > now) found = &s;
  return found;
}

std::optional<std::string> ConsoleAuth::csrfToken(const std::string& session_id, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const Session* s = find(session_id, now);
  if (!s) return std::nullopt;
  return s->csrf;
}

bool ConsoleAuth::csrfMatches(const std::string& session_id, const std::string& token,
                              Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const Session* s = find(session_id, now);
  return s && equalConstantTime(s->csrf, token);
}

double ConsoleAuth::secondsLeft(const std::string& session_id, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const Session* s = find(session_id, now);
  return s ? std::chrono::duration<double>(s->expires - now).count() : 0.0;
}

void ConsoleAuth::logout(const std::string& session_id) {
  std::lock_guard lock(mutex_);
  std::erase_if(sessions_, [&](const Session& s) { return equalConstantTime(s.id, session_id); });
}

void ConsoleAuth::setPasswordHash(std::string password_hash, std::chrono::minutes session_length) {
  std::lock_guard lock(mutex_);
  if (password_hash != hash_) sessions_.clear();
  hash_ = std::move(password_hash);
  session_length_ = session_length;
}

std::size_t ConsoleAuth::sessionCount() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

}  // namespace holo::kiosk
