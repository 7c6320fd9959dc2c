// A figure written into a Markdown table cell: printf-formatted, "n/a" where it is not a number
// (a method that produced nothing to score).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace holo::eval {

inline std::string tableNumber(double v, const char* format) {
  if (!std::isfinite(v)) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

}  // namespace holo::eval
