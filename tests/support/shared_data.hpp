// Where the real test data lives: $HOLO_SHARED_DATA, else ../shared/data beside the source tree.
// Tests that need it call HOLO_REQUIRE_SHARED_DATA("hdri/x.hdr"): when the file is absent it skips
// the test with a clear message (a user's fresh clone has no ../shared), or fails it when the
// environment sets HOLO_REQUIRE_SHARED_DATA=1 (CI, .ci/run), so missing data cannot pass as skips.
#pragma once

#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace holo::test {

inline std::filesystem::path sharedDataDir() {
  if (const char* env = std::getenv("HOLO_SHARED_DATA")) return env;
  return std::filesystem::path(HOLO_SOURCE_DIR).parent_path() / "shared" / "data";
}

inline std::filesystem::path sharedData(const std::string& relative) {
  return sharedDataDir() / relative;
}

inline bool sharedDataRequired() {
  const char* env = std::getenv("HOLO_REQUIRE_SHARED_DATA");
  return env != nullptr && std::string(env) == "1";
}

// A fresh, empty folder under the build tree for one test's files.
inline std::filesystem::path scratchDir(const std::string& name) {
  const auto dir = std::filesystem::path(HOLO_BINARY_DIR) / "test-scratch" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace holo::test

#define HOLO_REQUIRE_SHARED_DATA(relative)                                                         \
  do {                                                                                             \
    if (!std::filesystem::exists(::holo::test::sharedData(relative))) {                            \
      if (::holo::test::sharedDataRequired())                                                      \
        GTEST_FAIL() << "shared test data absent: " << ::holo::test::sharedData(relative).string() \
                     << " (HOLO_REQUIRE_SHARED_DATA=1: CI must have ../shared/data)";              \
      GTEST_SKIP() << "shared test data absent: " << ::holo::test::sharedData(relative).string()   \
                   << " (set HOLO_SHARED_DATA or place ../shared/data beside the repository)";     \
    }                                                                                              \
  } while (0)
