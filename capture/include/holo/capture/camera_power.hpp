// Injected power cuts (the kiosk's tests and soak runs, never a configuration): one switch per
// camera index of the process (0..3, one per pyramid face), all on at start. setCameraPowered(i,
// false) cuts camera i as if its power were pulled, for every source that honours the switches
// (the simulated cameras, holo::simulated::SimulatedSource): it goes quiet (grab times out, so
// the capture thread declares it disconnected after its silence timeout) and open() fails until
// it is switched on again; then it restarts as a rebooted camera would. Sources of real devices
// and recordings ignore them.
#pragma once

namespace holo::capture {

inline constexpr int kPowerSwitchCount = 4;

// Both throw InputError when `camera` is not 0..kPowerSwitchCount-1. Thread-safe.
void setCameraPowered(int camera, bool powered);
bool cameraPowered(int camera);

}  // namespace holo::capture
