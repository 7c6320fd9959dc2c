// Faults injected on purpose, for the kiosk's tests and soak runs only. Nothing in a product
// configuration can turn them on: they come from a file named by the environment variable
// HOLO_KIOSK_TEST_FAULTS, re-read whenever it changes, so a test can switch faults on and off
// while the kiosk runs. One fault a line, `#` comments:
//
//   slow_ms 120     every frame at the best quality takes 120 ms longer (halved per level
//                   down: an overloaded renderer that lower quality relieves)
//   fail_every 50   every 50th frame throws (a render error)
//   freeze_s 4      the next frame hangs for 4 s (a hung render), once per change of the file
//   black 1         frames are presented black although the museum is open (a broken source)
//   camera_off 2    camera 2 is switched off (a pulled cable, a camera that lost power) until a
//                   version of the file without the line; one line per camera
//
// A line that does not parse is logged and ignored: the test sees it in the log.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace holo::kiosk {

struct InjectedFaults {
  double slow_ms = 0;           // at quality level 0
  std::int64_t fail_every = 0;  // 0 = never
  double freeze_s = 0;          // pending hang, consumed by the next frame
  bool black = false;
  std::vector<int> cameras_off;  // camera indices, ascending, each once; the frame source applies them
};

class FaultInjector {
 public:
  // Reads HOLO_KIOSK_TEST_FAULTS; without it the injector is inert.
  static FaultInjector fromEnvironment();
  explicit FaultInjector(std::optional<std::filesystem::path> file = std::nullopt);

  bool active() const { return file_.has_value(); }
  // Call at the start of each frame: re-reads the file when it changed (checked at most every
  // 100 ms), sleeps for slow_ms and any pending freeze, throws holo::Error on a failing frame.
  // Returns the faults in force, for the frame source (black).
  InjectedFaults beginFrame(std::int64_t frame_index, int quality_level, bool blank);

 private:
  void reload();
  std::optional<std::filesystem::path> file_;
  std::optional<std::filesystem::file_time_type> stamp_;
  std::chrono::steady_clock::time_point last_check_{};
  InjectedFaults faults_;
};

}  // namespace holo::kiosk
