// The newest lines of the program's log (log.hpp), kept in memory for the technician's console to
// show without reading the journal: the last kLogTailLines lines, each formatted
// "2026-12-02 16:05:00.123 warning message" (UTC), whatever the logger's level let through.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace holo {

inline constexpr std::size_t kLogTailLines = 200;
// The newest `max_lines` lines (at most kLogTailLines), oldest first. Thread-safe.
std::vector<std::string> logTail(std::size_t max_lines = kLogTailLines);

}  // namespace holo
