#include "holo/kiosk/fault_injector.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::kiosk {

FaultInjector FaultInjector::fromEnvironment() {
  const char* file = std::getenv("HOLO_KIOSK_TEST_FAULTS");
  if (!file || !*file) return FaultInjector();
  HOLO_LOG_WARN("test fault injection from {} (HOLO_KIOSK_TEST_FAULTS)", file);
  return FaultInjector(std::filesystem::path(file));
}

FaultInjector::FaultInjector(std::optional<std::filesystem::path> file) : file_(std::move(file)) {}

void FaultInjector::reload() {
  std::error_code ec;
  const auto stamp = std::filesystem::last_write_time(*file_, ec);
  if (ec) {  // no file (yet, or any more): no faults
    if (stamp_) faults_ = {};
    stamp_.reset();
    return;
  }
  if (stamp_ && *stamp_ == stamp) return;
  stamp_ = stamp;
  InjectedFaults faults;
  std::ifstream in(*file_);
  std::string line;
  while (std::getline(in, line)) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string key;
    double value = 0;
    if (!(words >> key)) continue;
    if (!(words >> value)) {
      HOLO_LOG_WARN("test faults {}: '{}' needs a number", file_->string(), key);
      continue;
    }
    if (key == "slow_ms")
      faults.slow_ms = value;
    else if (key == "fail_every")
      faults.fail_every = static_cast<std::int64_t>(value);
    else if (key == "freeze_s")
      faults.freeze_s = value;
    else if (key == "black")
      faults.black = value != 0;
    else if (key == "camera_off")
      faults.cameras_off.push_back(static_cast<int>(value));
    else
      HOLO_LOG_WARN("test faults {}: unknown fault '{}'", file_->string(), key);
  }
  std::sort(faults.cameras_off.begin(), faults.cameras_off.end());
  faults.cameras_off.erase(std::unique(faults.cameras_off.begin(), faults.cameras_off.end()),
                           faults.cameras_off.end());
  faults_ = faults;
  std::string off;
  for (const int camera : faults_.cameras_off) {
    if (!off.empty()) off += ',';
    off += std::to_string(camera);
  }
  HOLO_LOG_WARN("test faults now: slow_ms {} fail_every {} freeze_s {} black {} cameras_off [{}]",
                faults_.slow_ms, faults_.fail_every, faults_.freeze_s, faults_.black, off);
}

InjectedFaults FaultInjector::beginFrame(std::int64_t frame_index, int quality_level, bool blank) {
  if (!file_) return {};
  const auto now = std::chrono::steady_clock::now();
  if (now - last_check_ >= std::chrono::milliseconds(100)) {
    last_check_ = now;
    reload();
  }
  InjectedFaults current = faults_;
  if (faults_.freeze_s > 0) {
    HOLO_LOG_WARN("test fault: frame {} hangs for {} s", frame_index, faults_.freeze_s);
    std::this_thread::sleep_for(std::chrono::duration<double>(faults_.freeze_s));
    faults_.freeze_s = 0;  // once per change of the file
  }
  if (faults_.slow_ms > 0 && !blank)
    std::this_thread::sleep_for(
        std::chrono::duration<double, std::milli>(faults_.slow_ms / (1 << quality_level)));
  if (faults_.fail_every > 0 && frame_index % faults_.fail_every == 0)
    throw Error("injected render failure at frame " + std::to_string(frame_index));
  return current;
}

}  // namespace holo::kiosk
