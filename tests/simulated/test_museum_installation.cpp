// The live simulated museum reads its hall's panorama where the hall is: the pyramid's base and a
// sphere of the hall's mean distance around the panorama's capture point, the proxy the
// evaluations measure (tests/eval's ReflectionScene tests compare the two); a hall with no
// geometry keeps it at infinity, and the loop's panorama_at_infinity puts any hall there.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "shared_data.hpp"

namespace holo::simulated {
namespace {

constexpr int kPanoramaWidth = 64;

TEST(SimulatedInstallation, PlacesTheHallsPanoramaAtItsMeanDistanceAboveTheBase) {
  const pipeline::Installation installation = museumInstallation("museum", /*paced=*/false, kPanoramaWidth);
  const reflect::PanoramaProxy& proxy = installation.panorama_proxy;
  ASSERT_FALSE(proxy.infinite());
  // The gallery's walls, floor and ceiling average about 4 m from the capture point.
  EXPECT_GT(proxy.radius, 3.0f);
  EXPECT_LT(proxy.radius, 6.0f);
  EXPECT_EQ(proxy.base_half_width, sim::kBaseHalfWidth);
  EXPECT_EQ(proxy.centre, sim::loadScene("museum").panorama_position);
  // A smaller hall is nearer.
  EXPECT_LT(museumInstallation("room", false, kPanoramaWidth).panorama_proxy.radius, proxy.radius);
}

TEST(SimulatedInstallation, AHallWithoutGeometryKeepsThePanoramaAtInfinity) {
  const std::filesystem::path dir = test::scratchDir("simulated_installation_" + std::to_string(getpid()));
  const std::filesystem::path scene = dir / "no_hall.yaml";
  std::ofstream(scene) << "base: museum\nhall: none\nvisitors: 0\n";
  const pipeline::Installation installation = museumInstallation(scene.string(), false, kPanoramaWidth);
  EXPECT_TRUE(installation.panorama_proxy.infinite());
  EXPECT_EQ(installation.panorama_proxy.base_half_width, 0.0f);
}

TEST(SimulatedInstallation, TheLoopReadsThePanoramaThroughItUnlessAskedForInfinity) {
  pipeline::FrameLoopOptions options;
  options.view_size = 32;
  options.panorama_width = kPanoramaWidth;
  const reflect::PanoramaProxy expected =
      museumInstallation(options.scene, false, kPanoramaWidth).panorama_proxy;
  const pipeline::FrameLoop loop(options, installationFor(options), nullptr);
  EXPECT_EQ(loop.ibl().proxy().radius, expected.radius);
  EXPECT_EQ(loop.ibl().proxy().base_half_width, expected.base_half_width);
  options.panorama_at_infinity = true;
  const pipeline::FrameLoop at_infinity(options, installationFor(options), nullptr);
  EXPECT_TRUE(at_infinity.ibl().proxy().infinite());
  EXPECT_EQ(at_infinity.ibl().proxy().base_half_width, 0.0f);
}

}  // namespace
}  // namespace holo::simulated
