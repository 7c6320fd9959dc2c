#include <gtest/gtest.h>
#include <cstdlib>
#include <ctime>

#include "holo/core/error.hpp"
#include "holo/kiosk/opening_hours.hpp"

namespace holo::kiosk {
namespace {

constexpr int kMon = 0, kFri = 4, kSat = 5, kSun = 6;
int at(int h, int m) {
  return h * 60 + m;
}

OpeningHours parse(const std::string& text) {
  return OpeningHours::parse(text, "test.yaml", "kiosk.opening_hours");
}

TEST(OpeningHours, WeekdaysAndSaturday) {
  const auto h = parse("Mon-Fri 09:00-18:00; Sat 10:00-16:00");
  EXPECT_FALSE(h.alwaysOpen());
  EXPECT_FALSE(h.isOpenAt(kMon, at(8, 59)));
  EXPECT_TRUE(h.isOpenAt(kMon, at(9, 0)));
  EXPECT_TRUE(h.isOpenAt(kFri, at(17, 59)));
  EXPECT_FALSE(h.isOpenAt(kFri, at(18, 0)));  // the end is exclusive
  EXPECT_FALSE(h.isOpenAt(kSat, at(9, 30)));
  EXPECT_TRUE(h.isOpenAt(kSat, at(12, 0)));
  EXPECT_FALSE(h.isOpenAt(kSun, at(12, 0)));  // not named: closed
}

TEST(OpeningHours, ListsSplitDaysClosedAndWholeDays) {
  const auto h = parse("mon,WED 09:00-12:00,13:00-17:30; Sun closed; Sat 00:00-24:00");
  EXPECT_TRUE(h.isOpenAt(kMon, at(11, 0)));
  EXPECT_FALSE(h.isOpenAt(kMon, at(12, 30)));  // lunch break
  EXPECT_TRUE(h.isOpenAt(2, at(17, 29)));
  EXPECT_FALSE(h.isOpenAt(1, at(11, 0)));  // Tuesday not listed
  EXPECT_FALSE(h.isOpenAt(kSun, at(11, 0)));
  EXPECT_TRUE(h.isOpenAt(kSat, at(0, 0)));
  EXPECT_TRUE(h.isOpenAt(kSat, at(23, 59)));
}

TEST(OpeningHours, PastMidnightAndWrappingDayRanges) {
  const auto h = parse("Sat-Sun 20:00-02:00");  // Sat-Sun wraps nothing; Sun's night runs into Monday
  EXPECT_TRUE(h.isOpenAt(kSat, at(23, 0)));
  EXPECT_TRUE(h.isOpenAt(kSun, at(1, 59)));  // Saturday's night
  EXPECT_TRUE(h.isOpenAt(kMon, at(1, 0)));   // Sunday's night
  EXPECT_FALSE(h.isOpenAt(kMon, at(2, 0)));
  EXPECT_FALSE(h.isOpenAt(kSat, at(1, 0)));  // Friday had no night opening
  const auto wrap = parse("Sat-Mon 10:00-11:00");
  EXPECT_TRUE(wrap.isOpenAt(kSun, at(10, 30)));
  EXPECT_TRUE(wrap.isOpenAt(kMon, at(10, 30)));
  EXPECT_FALSE(wrap.isOpenAt(1, at(10, 30)));
}

TEST(OpeningHours, EmptyIsAlwaysOpen) {
  const auto h = parse("  ");
  EXPECT_TRUE(h.alwaysOpen());
  EXPECT_TRUE(h.isOpenAt(kSun, at(3, 0)));
}

TEST(OpeningHours, BadTextNamesTheFieldAndTheClause) {
  for (const char* bad : {"Mon-Fri", "Mond 09:00-18:00", "Mon 9:00-18:00", "Mon 09:00-25:00",
                          "Mon 09:60-10:00", "Mon 09:00", "Mon 10:00-10:00", "Mon 24:00-02:00"}) {
    try {
      parse(bad);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("test.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find("kiosk.opening_hours"), std::string::npos) << what;
    }
  }
}

// A fixed instant under two time zones: the schedule follows local wall-clock time.
TEST(OpeningHours, FollowsTheLocalTimeZone) {
  const char* old_tz = std::getenv("TZ");
  const std::string saved = old_tz ? old_tz : "";
  const auto h = parse("Mon-Fri 09:00-18:00");
  // 2026-11-23 (a Monday) 08:30 UTC.
  const auto instant = std::chrono::system_clock::from_time_t(1795422600);
  setenv("TZ", "UTC", 1);
  tzset();
  EXPECT_FALSE(h.isOpen(instant));  // 08:30 in London-in-winter: not yet open
  setenv("TZ", "Europe/Berlin", 1);
  tzset();
  EXPECT_TRUE(h.isOpen(instant));  // 09:30 in Berlin: open
  setenv("TZ", "America/New_York", 1);
  tzset();
  EXPECT_FALSE(h.isOpen(instant));  // 03:30 in New York
  if (old_tz)
    setenv("TZ", saved.c_str(), 1);
  else
    unsetenv("TZ");
  tzset();
}

}  // namespace
}  // namespace holo::kiosk
