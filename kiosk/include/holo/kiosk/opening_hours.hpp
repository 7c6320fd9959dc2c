// The museum's opening hours: outside them the kiosk blanks the monitors (black frames) and
// resumes by itself when the museum opens, without a restart.
//
// Syntax (one string, clauses separated by ';'):
//   "Mon-Fri 09:00-18:00; Sat 10:00-16:00"
//   "Mon,Wed 09:00-12:00,13:00-17:30; Sun closed"
//   "Fri 20:00-02:00"          (an end before the start runs past midnight into the next day)
//   "daily 08:00-24:00"        ("daily" = Mon-Sun; 24:00 is the end of the day)
// Days are Mon Tue Wed Thu Fri Sat Sun (case-insensitive), as single days, ranges (Sat-Mon
// wraps) or comma lists. A day named in no clause is closed. An empty string means always open.
// Times are wall-clock local time of the machine (TZ / /etc/localtime), so daylight saving time
// is followed without configuration.
#pragma once

#include <array>
#include <chrono>
#include <string>
#include <vector>

namespace holo::kiosk {

class OpeningHours {
 public:
  // Always open.
  OpeningHours() = default;
  // Throws InputError(origin, field, ...) naming the clause that does not parse.
  static OpeningHours parse(const std::string& text, const std::string& origin, const std::string& field);

  bool alwaysOpen() const { return always_open_; }
  // weekday: 0 = Monday .. 6 = Sunday; minute: 0..1439 of local wall-clock time.
  bool isOpenAt(int weekday, int minute) const;
  // The same for an instant, converted with the machine's local time zone (localtime_r).
  bool isOpen(std::chrono::system_clock::time_point when) const;

 private:
  struct Interval {
    int begin;  // minute of the day, inclusive
    int end;    // minute of the day, exclusive (1440 = midnight)
  };
  bool always_open_ = true;
  // Per weekday (Mon = 0): the open intervals that start on that day, already split at
  // midnight (the part after midnight is stored on the next day).
  std::array<std::vector<Interval>, 7> days_{};
};

}  // namespace holo::kiosk
