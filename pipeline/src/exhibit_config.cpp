#include "holo/pipeline/exhibit_config.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "holo/relics/relics.hpp"

namespace holo::pipeline {
namespace {

// The `relic` field of `node`: a built-in relic's name or a glTF file beside the configuration.
void parseRelicField(const ConfigNode& node, std::string& builtin_relic, std::filesystem::path& relic_file) {
  const ConfigNode relic = node["relic"];
  const std::string relic_value = relic.as<std::string>();
  const std::vector<std::string> builtin = relics::relicNames();
  if (std::find(builtin.begin(), builtin.end(), relic_value) != builtin.end()) {
    builtin_relic = relic_value;
    return;
  }
  if (relic_value.empty())
    relic.fail("a glTF file (.gltf/.glb, relative to the configuration) or a built-in relic (" +
                   relics::relicNameList() + ")",
               "an empty text");
  relic_file = node.pathBesideFile(relic_value);
}

std::filesystem::path parsePanoramaField(const ConfigNode& node) {
  const ConfigNode panorama = node["panorama"];
  const std::string panorama_value = panorama.as<std::string>();
  if (panorama_value.empty())
    panorama.fail("an equirectangular HDR panorama (.hdr or .exr, relative to the configuration)",
                  "an empty text");
  return node.pathBesideFile(panorama_value);
}

double doubleInRange(const ConfigNode& node, const std::string& key, double fallback, double lo, double hi,
                     const std::string& what) {
  const double value = node.get<double>(key, fallback);
  if (!(value >= lo && value <= hi) || !std::isfinite(value)) node[key].fail(what);
  return value;
}

}  // namespace

RelicEntryConfig parseRelicEntry(const ConfigNode& entry, int index, const ExhibitConfig& section) {
  if (!entry.isMap()) entry.fail("a map with at least `relic:` (a glTF file or a built-in relic)");
  entry.rejectUnknownKeys({"relic", "fit_relic", "panorama", "hall_radius", "base_half_width", "scale",
                           "height", "yaw", "duration_s", "turntable_deg_per_s", "crossfade_s"});
  RelicEntryConfig config;
  config.index = index;
  config.name = entry["relic"].as<std::string>();
  parseRelicField(entry, config.builtin_relic, config.relic_file);
  config.fit_relic = entry.get<bool>("fit_relic", section.fit_relic);
  if (entry.has("panorama")) config.panorama_file = parsePanoramaField(entry);
  config.hall_radius_m = section.hall_radius_m;
  if (entry.has("hall_radius")) config.hall_radius_m = entry.getInRange("hall_radius", 10.0f, 0.5f, 1000.0f);
  if (entry.has("base_half_width"))
    config.base_half_width_m = entry.getInRange("base_half_width", 0.0f, 0.0f, 2.0f);
  if (config.base_half_width_m.value_or(section.base_half_width_m) > 0.0f && !config.hall_radius_m)
    entry[entry.has("base_half_width") ? "base_half_width" : "relic"].fail(
        "a base (base_half_width > 0) only with hall_radius (the base hides the hall only at its distance)");
  config.scale = entry.getInRange("scale", 1.0f, 0.01f, 100.0f);
  config.height_m = entry.getInRange("height", 0.0f, -1.0f, 2.0f);
  config.yaw_deg = entry.getInRange("yaw", 0.0f, -360.0f, 360.0f);
  config.duration_s =
      doubleInRange(entry, "duration_s", 60.0, 0.01, 86400.0, "seconds on show in [0.01, 86400]");
  config.turntable_deg_per_s = doubleInRange(entry, "turntable_deg_per_s", 0.0, -360.0, 360.0,
                                             "degrees per second in [-360, 360] (0: the relic stands still)");
  config.crossfade_s = doubleInRange(entry, "crossfade_s", 1.5, 0.0, 60.0, "seconds in [0, 60]");
  return config;
}

ExhibitConfig parseExhibitConfig(const ConfigNode& exhibit) {
  exhibit.rejectUnknownKeys({"relic", "relics", "fit_relic", "panorama", "hall_radius", "base_half_width",
                             "camera_exposure", "background_frames", "fps", "plinth"});
  ExhibitConfig config;
  const bool playlist = exhibit.has("relics");
  if (playlist && exhibit.has("relic"))
    exhibit["relic"].fail("no relic: beside relics: (the playlist names every relic)");
  if (!playlist) parseRelicField(exhibit, config.builtin_relic, config.relic_file);
  config.fit_relic = exhibit.get<bool>("fit_relic", false);
  if (!playlist || exhibit.has("panorama")) config.panorama_file = parsePanoramaField(exhibit);

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
  if (exhibit.has("plinth")) config.plinth = parsePlinth(exhibit["plinth"]);

  if (!playlist) return config;
  const ConfigNode relics = exhibit["relics"];
  if (!relics.isSequence() || relics.size() == 0)
    relics.fail("a list of relics, each `- relic: FILE or BUILT-IN NAME` with its settings");
  for (std::size_t i = 0; i < relics.size(); ++i) {
    const ConfigNode entry = relics[i];
    // The entry's name for the report, when it has a readable one.
    std::string name = "?";
    if (entry.isMap() && entry.has("relic") && entry["relic"].yaml().IsScalar())
      name = entry["relic"].yaml().Scalar();
    try {
      config.relics.push_back(parseRelicEntry(entry, static_cast<int>(i), config));
    } catch (const InputError& e) {
      config.relic_problems.push_back("entry " + std::to_string(i) + " (" + name + "): " + e.what());
    }
  }
  if (config.relics.empty()) {
    std::string why;
    for (const std::string& problem : config.relic_problems) why += (why.empty() ? "" : "; ") + problem;
    relics.fail("at least one entry that parses", why);
  }
  config.builtin_relic = config.relics.front().builtin_relic;
  config.relic_file = config.relics.front().relic_file;
  config.fit_relic = config.relics.front().fit_relic;
  return config;
}

}  // namespace holo::pipeline
