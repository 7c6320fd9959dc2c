#include "holo/capture/camera_power.hpp"

#include <array>
#include <atomic>
#include <string>

#include "holo/core/error.hpp"

namespace holo::capture {
namespace {

std::atomic<bool>& powerSwitch(int camera) {
  static std::array<std::atomic<bool>, kPowerSwitchCount> switches{true, true, true, true};
  if (camera < 0 || camera >= kPowerSwitchCount)
    throw InputError("", "camera", "0.." + std::to_string(kPowerSwitchCount - 1), std::to_string(camera));
  return switches[static_cast<std::size_t>(camera)];
}

}  // namespace

void setCameraPowered(int camera, bool powered) {
  powerSwitch(camera) = powered;
}

bool cameraPowered(int camera) {
  return powerSwitch(camera);
}

}  // namespace holo::capture
