#include "holo/kiosk/opening_hours.hpp"

#include <algorithm>
#include <cctype>
#include <ctime>
#include <sstream>

#include "holo/core/error.hpp"

namespace holo::kiosk {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, sep)) parts.push_back(trim(part));
  return parts;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

int dayIndex(const std::string& name) {
  static const std::array<const char*, 7> kNames{"mon", "tue", "wed", "thu", "fri", "sat", "sun"};
  const std::string key = lower(name);
  for (int i = 0; i < 7; ++i)
    if (key == kNames[static_cast<std::size_t>(i)]) return i;
  return -1;
}

// "HH:MM" -> minute of the day, 0..1440; -1 when malformed.
int parseTime(const std::string& text) {
  if (text.size() != 5 || text[2] != ':') return -1;
  for (const int i : {0, 1, 3, 4})
    if (!std::isdigit(static_cast<unsigned char>(text[static_cast<std::size_t>(i)]))) return -1;
  const int h = std::stoi(text.substr(0, 2));
  const int m = std::stoi(text.substr(3, 2));
  if (m > 59 || h > 24 || (h == 24 && m != 0)) return -1;
  return h * 60 + m;
}

}  // namespace

OpeningHours OpeningHours::parse(const std::string& text, const std::string& origin,
                                 const std::string& field) {
  OpeningHours hours;
  if (trim(text).empty()) return hours;
  hours.always_open_ = false;
  for (const auto& clause : split(text, ';')) {
    if (clause.empty()) continue;
    const auto fail = [&](const std::string& what) {
      throw InputError(origin, field,
                       "opening hours like \"Mon-Fri 09:00-18:00; Sat 10:00-16:00\" (" + what + ")", clause);
    };
    const auto space = clause.find_first_of(" \t");
    if (space == std::string::npos) fail("days, a space, then times or 'closed'");
    const std::string days_text = clause.substr(0, space);
    const std::string times_text = trim(clause.substr(space + 1));

    std::vector<int> days;
    if (lower(days_text) == "daily") {
      days = {0, 1, 2, 3, 4, 5, 6};
    } else {
      for (const auto& item : split(days_text, ',')) {
        const auto dash = item.find('-');
        if (dash == std::string::npos) {
          const int d = dayIndex(item);
          if (d < 0) fail("unknown day '" + item + "', expected Mon..Sun");
          days.push_back(d);
        } else {
          const int a = dayIndex(item.substr(0, dash));
          const int b = dayIndex(item.substr(dash + 1));
          if (a < 0 || b < 0) fail("unknown day range '" + item + "', expected e.g. Mon-Fri");
          for (int d = a;; d = (d + 1) % 7) {
            days.push_back(d);
            if (d == b) break;
          }
        }
      }
    }
    if (lower(times_text) == "closed") continue;
    for (const auto& range : split(times_text, ',')) {
      const auto dash = range.find('-');
      if (dash == std::string::npos) fail("time range '" + range + "', expected HH:MM-HH:MM");
      const int begin = parseTime(trim(range.substr(0, dash)));
      const int end = parseTime(trim(range.substr(dash + 1)));
      if (begin < 0 || end < 0 || begin == 1440)
        fail("time range '" + range + "', expected HH:MM-HH:MM within 00:00..24:00");
      if (begin == end) fail("empty time range '" + range + "'");
      for (const int d : days) {
        auto& today = hours.days_[static_cast<std::size_t>(d)];
        if (end > begin) {
          today.push_back({begin, end});
        } else {  // past midnight: the rest of today, then the start of tomorrow
          today.push_back({begin, 1440});
          if (end > 0) hours.days_[static_cast<std::size_t>((d + 1) % 7)].push_back({0, end});
        }
      }
    }
  }
  return hours;
}

bool OpeningHours::isOpenAt(int weekday, int minute) const {
  if (always_open_) return true;
  if (weekday < 0 || weekday > 6 || minute < 0 || minute >= 1440) return false;
  const auto& today = days_[static_cast<std::size_t>(weekday)];
  return std::any_of(today.begin(), today.end(),
                     [&](const Interval& i) { return minute >= i.begin && minute < i.end; });
}

bool OpeningHours::isOpen(std::chrono::system_clock::time_point when) const {
  if (always_open_) return true;
  const std::time_t t = std::chrono::system_clock::to_time_t(when);
  std::tm local{};
  localtime_r(&t, &local);
  const int weekday = (local.tm_wday + 6) % 7;  // tm: Sunday = 0
  return isOpenAt(weekday, local.tm_hour * 60 + local.tm_min);
}

}  // namespace holo::kiosk
