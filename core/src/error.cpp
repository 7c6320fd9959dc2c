#include "holo/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace holo {

namespace {
std::string describe(const std::string& file, const std::string& field, const std::string& expected,
                     const std::string& got) {
  std::string message;
  if (!file.empty()) message += file + ": ";
  if (!field.empty()) message += field + ": ";
  message += "expected " + expected;
  if (!got.empty()) message += ", got " + got;
  return message;
}
}  // namespace

InputError::InputError(std::string file, std::string field, std::string expected, std::string got)
    : Error(describe(file, field, expected, got)), file_(std::move(file)), field_(std::move(field)) {}

void assertionFailed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "holopyramid: internal error: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace holo
