// Subcommands of the `holopyramid` program. Each app/cmd_*.cpp file registers its subcommand
// with a static HOLO_REGISTER_COMMAND; main() builds the CLI11 tree from the registry (a name
// with a space, "eval depth", lands under the group "eval"). A
// command's run function returns the process exit code; InputError and Error thrown from it are
// reported as one line on stderr with exit code 2 and 1.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace holo::app {

struct Command {
  std::string name;
  // Adds the subcommand's options to `sub`; returns the function that runs it once parsed.
  std::function<std::function<int()>(CLI::App& sub)> setup;
  std::string description;
};

bool registerCommand(Command command);

}  // namespace holo::app

#define HOLO_CONCAT_INNER(a, b) a##b
#define HOLO_CONCAT(a, b) HOLO_CONCAT_INNER(a, b)
#define HOLO_REGISTER_COMMAND(...)                                    \
  static const bool HOLO_CONCAT(holo_command_registered_, __LINE__) = \
      ::holo::app::registerCommand(__VA_ARGS__)
