// Cheap named statistics counters, printed at exit on request (--stats). A counter is a relaxed
// atomic; hot loops should count locally and add once per tile or frame. Names are
// "Category/What", e.g. "Capture/Frames dropped"; the report groups them by category.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>

namespace holo::stats {

// Returns the counter with this name, creating it at 0. The reference stays valid for the life
// of the program, so callers keep it in a static.
std::atomic<std::int64_t>& counter(const std::string& name);
inline void add(const std::string& name, std::int64_t n = 1) {
  counter(name).fetch_add(n, std::memory_order_relaxed);
}
std::map<std::string, std::int64_t> snapshot();
void print(std::ostream& out);
void resetAll();  // for tests

}  // namespace holo::stats
