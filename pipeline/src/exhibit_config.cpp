#include "holo/pipeline/exhibit_config.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "holo/relics/relics.hpp"

namespace holo::pipeline {

ExhibitConfig parseExhibitConfig(const ConfigNode& exhibit) {
  exhibit.rejectUnknownKeys({"relic", "fit_relic", "panorama", "hall_radius", "base_half_width",
                             "camera_exposure", "background_frames", "fps"});
  ExhibitConfig config;
  const ConfigNode relic = exhibit["relic"];
  const std::string relic_value = relic.as<std::string>();
  const std::vector<std::string> builtin = relics::relicNames();
  if (std::find(builtin.begin(), builtin.end(), relic_value) != builtin.end()) {
    config.builtin_relic = relic_value;
  } else {
    if (relic_value.empty())
      relic.fail("a glTF file (.gltf/.glb, relative to the configuration) or a built-in relic (" +
                     relics::relicNameList() + ")",
                 "an empty text");
    config.relic_file = exhibit.pathBesideFile(relic_value);
  }
  config.fit_relic = exhibit.get<bool>("fit_relic", false);

  const ConfigNode panorama = exhibit["panorama"];
  const std::string panorama_value = panorama.as<std::string>();
  if (panorama_value.empty())
    panorama.fail("an equirectangular HDR panorama (.hdr or .exr, relative to the configuration)",
                  "an empty text");
  config.panorama_file = exhibit.pathBesideFile(panorama_value);

  if (exhibit.has("hall_radius"))
    config.hall_radius_m = exhibit.getInRange("hall_radius", 10.0f, 0.5f, 1000.0f);
  config.base_half_width_m = exhibit.getInRange("base_half_width", 0.0f, 0.0f, 2.0f);
  // At infinity every point reads its own direction's pixel: a base there would hide nothing.
  if (config.base_half_width_m > 0.0f && !config.hall_radius_m)
    exhibit["base_half_width"].fail(
        "0 or absent without hall_radius (the base hides the hall only at its distance)");
  config.camera_exposure = exhibit.get<float>("camera_exposure", 1.0f);
  if (!(config.camera_exposure > 0.0f) || !std::isfinite(config.camera_exposure))
    exhibit["camera_exposure"].fail("a positive number");
  config.background_frames = exhibit.get<int>("background_frames", 30);
  if (config.background_frames < 0 || config.background_frames > 10000)
    exhibit["background_frames"].fail("a number of frames in 0..10000");
  config.fps = exhibit.get<double>("fps", 30.0);
  if (!(config.fps > 0.0 && config.fps <= 1000.0)) exhibit["fps"].fail("a frame rate in Hz in (0, 1000]");
  return config;
}

}  // namespace holo::pipeline
