// Runs the holopyramid binary under test (HOLO_APP_BINARY, set by holo_app_binary_test) with
// `arguments`, its output going to `log`; returns its exit status.
#pragma once

#include <filesystem>
#include <string>

#include "run_command.hpp"

namespace holo::test {

inline int runHolopyramid(const std::string& arguments, const std::filesystem::path& log) {
  return runCommand(std::string(HOLO_APP_BINARY) + " " + arguments, log);
}

}  // namespace holo::test
