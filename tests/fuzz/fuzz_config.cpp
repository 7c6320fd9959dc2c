// The YAML files an installer edits: the appliance configuration (its kiosk:, display: and
// capture: sections, through ConfigNode and yaml-cpp) and the calibration files (OpenCV
// FileStorage YAML, read with yaml-cpp). The first byte picks the reader; an appliance document
// goes through every section's parser, as the kiosk reads one file for all of them. Only
// holo::InputError may come out.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_files.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"
#include "holo/kiosk/kiosk_config.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  holo::initLogging(holo::LogLevel::Off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const auto dir = holo::fuzz::scratchDir();
  try {
    switch (data[0] % 4) {
      case 0: {
        const holo::ConfigNode root = holo::ConfigNode::parse(std::string(text), "fuzz.yaml");
        try {
          (void)holo::kiosk::parseKioskConfig(root);
        } catch (const holo::InputError&) {
        }
        (void)holo::display::displayConfigOf(root);
        break;
      }
      case 1:
        holo::fuzz::writeBytes(dir / "capture.yaml", text);
        (void)holo::capture::loadCaptureConfig(dir / "capture.yaml");
        break;
      case 2:
        holo::fuzz::writeBytes(dir / "camera_X.yml", text);
        (void)holo::calib::loadCameraCalibration(dir / "camera_X.yml");
        break;
      default:
        holo::fuzz::writeBytes(dir / "pyramid.yml", text);
        (void)holo::calib::loadPyramidCalibration(dir / "pyramid.yml");
        break;
    }
  } catch (const holo::InputError&) {
  }
  return 0;
}
