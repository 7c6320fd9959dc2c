// `holopyramid console-password [--file PATH]`: sets the technician's console password
// (docs/kiosk.md, "The technician's console"). The password comes from stdin, one line: asked
// twice without echo on a terminal, read as is from a pipe (scripts, tests). Only its argon2id
// hash is written, with mode 0600 (kiosk/console_auth.hpp).
#include <termios.h>
#include <unistd.h>

#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/kiosk/console_auth.hpp"

namespace holo::app {
namespace {

std::string readLine(bool terminal, const std::string& prompt) {
  termios saved{};
  if (terminal) {
    std::cerr << prompt << std::flush;
    tcgetattr(STDIN_FILENO, &saved);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  const bool got = static_cast<bool>(std::getline(std::cin, line));
  if (terminal) {
    tcsetattr(STDIN_FILENO, TCSANOW, &saved);
    std::cerr << "\n";
  }
  if (!got) throw InputError("stdin", "password", "the password on one line", "no input");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

int setPassword(const std::string& file) {
  const bool terminal = isatty(STDIN_FILENO) == 1;
  const std::string password = readLine(terminal, "New console password: ");
  if (terminal && readLine(true, "Again: ") != password)
    throw InputError("stdin", "password", "the same password twice", "two different ones");
  kiosk::writeConsoleSecret(file, password);
  std::cerr << "console password hash written to " << file
            << " (mode 0600); `systemctl reload holopyramid` to use it\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "console-password",
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>("/etc/holopyramid/console.secret");
      sub.add_option("--file", *file, "Where the password's hash goes (kiosk.console.secret_file)")
          ->capture_default_str();
      return [file] { return setPassword(*file); };
    },
    "Set the technician's console password (read from stdin; only its argon2id hash is stored)"});

}  // namespace holo::app
