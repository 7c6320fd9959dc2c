// `holopyramid run --live --config FILE` on GigE Vision cameras: Aravis's fake cameras (two
// cameras, each a colour and a depth device) in a network namespace of the test's own, with the
// fixtures of tests/capture (fake_gv_camera.hpp). The configuration names them by serial; their
// models come from calibration files. Skips where namespaces or the fake camera are not there.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../capture/fake_gv_camera.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/sim/museum.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr int kCameras = 2;  // each: a colour device and a depth device

std::string serial(int device) {
  return "HOLO-RUN-" + std::to_string(device);
}
std::string address(int device) {
  return "127.0.2." + std::to_string(device + 1);
}

TEST(RunAravis, TheFrameLoopRunsOnFakeGigECamerasNamedInTheConfiguration) {
  if (holo::test::findProgram("arv-fake-gv-camera-0.8").empty())
    GTEST_SKIP() << "arv-fake-gv-camera-0.8 not found (Debian package aravis-tools)";
  holo::test::NetworkNamespace netns("holo-run-" + std::to_string(::getpid()));
  std::vector<std::string> addresses;
  for (int d = 0; d < 2 * kCameras; ++d) addresses.push_back(address(d));
  if (const std::string why = netns.create(addresses); !why.empty())
    GTEST_SKIP() << "fake GigE cameras need a network namespace of their own: " << why;
  std::vector<std::unique_ptr<holo::test::FakeCamera>> devices;
  for (int d = 0; d < 2 * kCameras; ++d) {
    devices.push_back(std::make_unique<holo::test::FakeCamera>(netns.name(), address(d), serial(d)));
    ASSERT_TRUE(devices.back()->start());
  }

  const fs::path dir = holo::test::scratchDir("app_run_aravis");
  {
    std::ofstream scene(dir / "scene.yaml");
    scene << "base: museum\ncamera: {width: 320, height: 240, hfov_deg: 90, vfov_deg: 70, fps: 25}\n";
  }
  const holo::sim::Museum museum(holo::sim::loadScene((dir / "scene.yaml").string()));
  fs::create_directories(dir / "calibration");
  std::string cameras;
  for (int c = 0; c < kCameras; ++c) {
    const std::string colour = serial(2 * c), depth = serial(2 * c + 1);
    holo::calib::saveCameraCalibration(holo::calib::cameraCalibrationPath(dir / "calibration", colour),
                                       holo::calib::fromCameraModel(museum.camera(c), colour));
    cameras +=
        "    - face: " + std::to_string(c) + "\n      backend: aravis\n      color: {serial: \"" + colour +
        "\", pixel_format: BayerGB8, width: 320, height: 240, frame_rate: 25}\n"
        "      depth: {serial: \"" +
        depth + "\", pixel_format: Mono16, width: 320, height: 240, frame_rate: 25, depth_scale: 0.001}\n";
  }
  holo::saveHdr(dir / "hall.exr", museum.renderPanorama(128, 64));
  {
    std::ofstream config(dir / "aravis.yaml");
    // Two free-running fake devices per camera at 25 Hz: their frames arrive up to 20 ms apart.
    config << "capture:\n  calibration_dir: calibration\n  pair_tolerance_ms: 20\n  cameras:\n"
           << cameras
           << "exhibit:\n  relic: kettle\n  panorama: hall.exr\n  background_frames: 3\n  fps: 25\n"
              "display:\n  layout: cross\n  output_size: [144, 144]\n";
  }

  const fs::path out = dir / "out";
  const std::string log = (dir / "log.txt").string();
  const int rc =
      holo::test::runWithTimeout({"ip", "netns", "exec", netns.name(), HOLO_APP_BINARY, "run", "--headless",
                                  "--live", "--frames", "12", "--view-size", "48", "--png-every", "0",
                                  "--config", (dir / "aravis.yaml").string(), "--out", out.string()},
                                 log, 60s);
  std::ifstream log_in(log);
  const std::string text(std::istreambuf_iterator<char>(log_in), {});
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find("camera_" + serial(0) + ".yml"), std::string::npos) << text;
  EXPECT_NE(text.find("camera_" + serial(2) + ".yml"), std::string::npos) << text;

  std::ifstream in(out / "timing.json");
  ASSERT_TRUE(in.good()) << text;
  const nlohmann::json timing = nlohmann::json::parse(in);
  ASSERT_EQ(timing["frames"].get<int>(), 12);
  EXPECT_EQ(timing["non_finite_pixels"].get<long long>(), 0);
  EXPECT_EQ(timing["camera_frames"]["mode"], "live");
  EXPECT_GT(timing["camera_frames"]["produced"].get<long long>(), 0);
  int both_live = 0;
  for (const auto& frame : timing["per_frame"])
    both_live += frame["cameras_live"].get<int>() == kCameras ? 1 : 0;
  EXPECT_GE(both_live, 6) << "the fake cameras' frames did not reach the foreground stage";
}

}  // namespace
