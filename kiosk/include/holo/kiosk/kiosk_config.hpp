// The `kiosk:` section of the appliance's YAML configuration (/etc/holopyramid/holopyramid.yaml),
// and start-up that never fails on a bad file: a configuration that does not load or validate
// is replaced by the last good copy (saved after every successful load) or, failing that, by
// the factory defaults built into the program, and the reason is reported (log, STATUS=,
// health JSON). Every field is optional; unknown fields in `kiosk:` are errors, so a typo is
// reported instead of silently doing nothing.
//
//   kiosk:
//     opening_hours: "Mon-Fri 09:00-18:00; Sat 10:00-16:00"   # empty or absent: always on
//     max_fps: 30                  # frame pacing cap, also while blanked (then 2 fps)
//     status_interval_s: 1.0       # how often STATUS= and the health file are refreshed
//     health:
//       address: 127.0.0.1         # loopback only
//       port: 8787                 # 0 = any free port (tests); negative = no HTTP endpoint
//       file: /run/holopyramid/health.json   # empty = no file
//     console:                     # the technician's web console (docs/kiosk.md), off by default
//       enabled: false
//       address: 127.0.0.1         # a non-loopback address only when written here explicitly
//       port: 8788                 # 0 = any free port (tests)
//       secret_file: /etc/holopyramid/console.secret   # the password's argon2id hash, mode 0600
//       session_minutes: 60        # a login lasts this long, 1..1440
//     degradation:
//       frame_budget_ms: 40
//       quality_levels: [full, reduced, low, minimal]
//       headroom: 0.7
//       smoothing: 0.2
//       down_after_frames: 10
//       up_after_frames: 60
//       cooldown_frames: 30
//       recover_after_frames: 15
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "holo/core/config.hpp"
#include "holo/kiosk/degradation_policy.hpp"
#include "holo/kiosk/opening_hours.hpp"

namespace holo::kiosk {

// kiosk.console: where and how the technician's console listens (console_server.hpp).
struct ConsoleSettings {
  bool enabled = false;
  std::string address = "127.0.0.1";
  int port = 8788;
  std::filesystem::path secret_file = "/etc/holopyramid/console.secret";
  int session_minutes = 60;
};

struct KioskConfig {
  OpeningHours opening_hours;  // default: always open
  std::string opening_hours_text;
  double max_fps = 30.0;
  double status_interval_s = 1.0;
  std::string health_address = "127.0.0.1";
  int health_port = 8787;
  std::filesystem::path health_file = "/run/holopyramid/health.json";
  DegradationSettings degradation;
  ConsoleSettings console;
};

// The factory defaults as YAML text (the same values as KioskConfig{}), the last resort.
const std::string& factoryDefaultsYaml();

// Parses the `kiosk:` section of `root` (absent: defaults). Throws InputError naming the file and
// the dotted field.
KioskConfig parseKioskConfig(const ConfigNode& root);

struct LoadedConfig {
  ConfigNode root;  // the whole document used (other modules read their sections from it)
  KioskConfig kiosk;
  std::string source;   // the file's path, "last good copy (PATH)" or "factory defaults"
  std::string warning;  // empty when the configured file was used; else why it was not
};

// Loads `path`; `validate` may check other sections of the same document (e.g. display:) and
// throw InputError. On success the file's text is saved atomically to `last_good` (when not
// empty). On failure falls back to `last_good`, then to the factory defaults. Never throws for
// a bad or missing file. The last good copy is read as if it were at `path`, so relative paths
// in it resolve as they did when it was saved.
LoadedConfig loadConfigWithFallback(const std::filesystem::path& path, const std::filesystem::path& last_good,
                                    const std::function<void(const ConfigNode&)>& validate = {});

}  // namespace holo::kiosk
