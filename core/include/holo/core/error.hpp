// Errors the user can act on. The project's rule (after Open3D's):
//  * throw holo::InputError when input the user supplied (a file, a flag, a config field) is
//    wrong and the operation cannot give a meaningful result; its message names the file, the
//    field and what was expected;
//  * log a warning and go on when the data is usable after a documented repair (clamped NaN
//    pixels, a dropped camera frame) and count the repair in the statistics;
//  * assert (HOLO_ASSERT) only on the program's own invariants, never on input.
#pragma once

#include <stdexcept>
#include <string>

namespace holo {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "FILE: FIELD: expected WHAT[, got GOT]". Any part may be empty and is then left out.
class InputError : public Error {
 public:
  InputError(std::string file, std::string field, std::string expected, std::string got = {});

  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  std::string field_;
};

[[noreturn]] void assertionFailed(const char* expr, const char* file, int line);

}  // namespace holo

#define HOLO_ASSERT(expr) ((expr) ? void(0) : ::holo::assertionFailed(#expr, __FILE__, __LINE__))
