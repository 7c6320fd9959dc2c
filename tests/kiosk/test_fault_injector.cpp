// The test fault file: what each line turns on, and that camera faults follow the file.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/kiosk/fault_injector.hpp"
#include "shared_data.hpp"

namespace holo::kiosk {
namespace {

TEST(FaultInjector, CamerasOffAreSortedUniqueAndFollowTheFile) {
  const auto file = test::scratchDir("fault_injector") / "faults.txt";
  writeFileAtomically(file, "camera_off 3\ncamera_off 1  # cable pulled\ncamera_off 3\nfail_every 5\n");
  FaultInjector faults(file);
  const InjectedFaults first = faults.beginFrame(1, 0, false);
  EXPECT_EQ(first.cameras_off, (std::vector<int>{1, 3}));
  EXPECT_EQ(first.fail_every, 5);
  EXPECT_THROW(faults.beginFrame(5, 0, false), Error);

  // The file is re-read at most every 100 ms; a missing file means no faults.
  std::filesystem::remove(file);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  const InjectedFaults cleared = faults.beginFrame(5, 0, false);
  EXPECT_TRUE(cleared.cameras_off.empty());
  EXPECT_EQ(cleared.fail_every, 0);
}

TEST(FaultInjector, WithoutAFileNothingIsInjected) {
  FaultInjector none;
  EXPECT_FALSE(none.active());
  const InjectedFaults faults = none.beginFrame(0, 0, false);
  EXPECT_TRUE(faults.cameras_off.empty());
  EXPECT_FALSE(faults.black);
}

}  // namespace
}  // namespace holo::kiosk
