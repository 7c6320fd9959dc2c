#include "holo/core/stats.hpp"

#include <deque>
#include <iomanip>
#include <mutex>

namespace holo::stats {

namespace {
struct Registry {
  std::mutex mutex;
  std::map<std::string, std::atomic<std::int64_t>*> by_name;
  std::deque<std::atomic<std::int64_t>> storage;  // stable addresses
};
Registry& registry() {
  static Registry r;
  return r;
}
}  // namespace

std::atomic<std::int64_t>& counter(const std::string& name) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  auto it = r.by_name.find(name);
  if (it != r.by_name.end()) return *it->second;
  auto& c = r.storage.emplace_back(0);
  r.by_name.emplace(name, &c);
  return c;
}

std::map<std::string, std::int64_t> snapshot() {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  std::map<std::string, std::int64_t> out;
  for (const auto& [name, c] : r.by_name) out[name] = c->load(std::memory_order_relaxed);
  return out;
}

void print(std::ostream& out) {
  std::string category;
  out << "Statistics:\n";
  for (const auto& [name, value] : snapshot()) {
    const auto slash = name.find('/');
    const std::string cat = slash == std::string::npos ? "" : name.substr(0, slash);
    const std::string what = slash == std::string::npos ? name : name.substr(slash + 1);
    if (cat != category) {
      category = cat;
      out << "  " << category << "\n";
    }
    out << "    " << std::left << std::setw(40) << what << std::right << std::setw(14) << value << "\n";
  }
}

void resetAll() {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  for (auto& [name, c] : r.by_name) c->store(0);
}

}  // namespace holo::stats
