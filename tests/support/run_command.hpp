// Runs a command line through the shell as a user would, its output (stdout and stderr) going to
// `log`, and returns its exit status (128 + the signal when a signal ended it).
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace holo::test {

inline int runCommand(const std::string& command_line, const std::filesystem::path& log) {
  const std::string command = command_line + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace holo::test
