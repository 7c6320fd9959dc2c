// The YAML files an installer edits: the appliance configuration (its kiosk:, display:, exhibit:
// and capture: sections, through ConfigNode and yaml-cpp) and the calibration files (OpenCV
// FileStorage YAML, read with yaml-cpp). The first byte picks the reader; an appliance document
// goes through every section's parser, as the kiosk reads one file for all of them. Only
// holo::InputError may come out, and a parsed exhibit: section must keep its promises (one relic,
// paths resolved beside the configuration file, every number in its range).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_files.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"
#include "holo/kiosk/kiosk_config.hpp"
#include "holo/pipeline/exhibit_config.hpp"
#include "holo/relics/relics.hpp"

namespace {

// An appliance document's origin: an existing file, so that relative paths resolve beside it as
// in the kiosk. The exhibit parser must not open what they name (nothing is there).
const std::string& applianceFile() {
  static const std::string file = [] {
    const auto path = holo::fuzz::scratchDir() / "appliance.yaml";
    holo::fuzz::writeBytes(path, "");
    return path.string();
  }();
  return file;
}

void checkExhibit(const holo::ConfigNode& root) {
  const holo::pipeline::ExhibitConfig exhibit = holo::pipeline::parseExhibitConfig(root["exhibit"]);
  const std::vector<std::string> builtin = holo::relics::relicNames();
  if (exhibit.builtin_relic.empty() == exhibit.relic_file.empty()) __builtin_trap();
  if (!exhibit.builtin_relic.empty() &&
      std::find(builtin.begin(), builtin.end(), exhibit.builtin_relic) == builtin.end())
    __builtin_trap();
  if (exhibit.builtin_relic.empty() && !exhibit.relic_file.is_absolute()) __builtin_trap();
  if (!exhibit.panorama_file.is_absolute() && !(exhibit.playlist() && exhibit.panorama_file.empty()))
    __builtin_trap();
  for (const holo::pipeline::RelicEntryConfig& entry : exhibit.relics) {
    if (entry.builtin_relic.empty() == entry.relic_file.empty()) __builtin_trap();
    if (entry.builtin_relic.empty() && !entry.relic_file.is_absolute()) __builtin_trap();
    if (!entry.panorama_file.empty() && !entry.panorama_file.is_absolute()) __builtin_trap();
    if (!(entry.scale >= 0.01f && entry.scale <= 100.0f) ||
        !(entry.height_m >= -1.0f && entry.height_m <= 2.0f) ||
        !(entry.yaw_deg >= -360.0f && entry.yaw_deg <= 360.0f))
      __builtin_trap();
    if (!(entry.duration_s >= 0.01 && entry.duration_s <= 86400.0) ||
        !(entry.turntable_deg_per_s >= -360.0 && entry.turntable_deg_per_s <= 360.0) ||
        !(entry.crossfade_s >= 0.0 && entry.crossfade_s <= 60.0))
      __builtin_trap();
    if (entry.hall_radius_m && !(*entry.hall_radius_m >= 0.5f && *entry.hall_radius_m <= 1000.0f))
      __builtin_trap();
    if (entry.base_half_width_m.value_or(exhibit.base_half_width_m) > 0.0f && !entry.hall_radius_m)
      __builtin_trap();
  }
  if (exhibit.hall_radius_m && !(*exhibit.hall_radius_m >= 0.5f && *exhibit.hall_radius_m <= 1000.0f))
    __builtin_trap();
  if (!(exhibit.base_half_width_m >= 0.0f && exhibit.base_half_width_m <= 2.0f)) __builtin_trap();
  if (exhibit.base_half_width_m > 0.0f && !exhibit.hall_radius_m) __builtin_trap();
  if (!(exhibit.camera_exposure > 0.0f) || !std::isfinite(exhibit.camera_exposure)) __builtin_trap();
  if (exhibit.background_frames < 0 || exhibit.background_frames > 10000) __builtin_trap();
  if (!(exhibit.fps > 0.0 && exhibit.fps <= 1000.0)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  holo::initLogging(holo::LogLevel::Off);
  (void)applianceFile();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const auto dir = holo::fuzz::scratchDir();
  try {
    switch (data[0] % 4) {
      case 0: {
        const holo::ConfigNode root = holo::ConfigNode::parse(std::string(text), applianceFile());
        try {
          (void)holo::kiosk::parseKioskConfig(root);
        } catch (const holo::InputError&) {
        }
        try {
          checkExhibit(root);
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
