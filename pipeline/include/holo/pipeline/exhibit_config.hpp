// The `exhibit:` section of a configuration document, parsed without touching the files it names:
//
//   exhibit:
//     relic: relics/amphora.glb   # glTF 2.0 file (relative to this file) or vase|kettle|tripod|sphere
//     fit_relic: false            # scale and centre a relic file on the pedestal (built-in: always)
//     panorama: hall.hdr          # equirectangular linear HDR of the hall (.hdr or .exr)
//     hall_radius: 8.0            # metres from the panorama's capture point to the hall's walls:
//                                 # reflections get the hall's parallax (reflect::PanoramaProxy);
//                                 # absent: the hall is infinitely far (no parallax)
//     base_half_width: 0.3        # metres, half the width of the pyramid's square base (its top is
//                                 # y = 0): the panorama's pixels below the relic lie on it, and
//                                 # it hides the hall behind it; needs hall_radius; absent: 0, no base
//     camera_exposure: 1.0        # the cameras' exposure: radiance = linear(sRGB) / exposure
//     background_frames: 30       # first frames of every camera that only teach the background
//     fps: 30                     # the cameras' frame rate (timing of the MP4, eye smoothing)
//     plinth:                     # optional: a virtual plinth under the relic (core/plinth.hpp)
//       half_width: 0.12          # metres; height, gap (metres) and albedo as there
//
// Or a playlist: `relics:` instead of `relic:`, the relics shown in turn (docs/kiosk.md):
//
//   exhibit:
//     panorama: hall.hdr          # every entry's hall unless it names its own; optional here
//     hall_radius: 8.0            # (and base_half_width, fit_relic): the entries' defaults
//     relics:
//       - relic: relics/amphora.glb
//         panorama: other_hall.hdr  # optional: this entry's hall (hall_radius, base_half_width too)
//         fit_relic: true           # optional, the section's by default
//         scale: 1.0                # times the fitted (or the file's) size, in [0.01, 100]
//         height: 0.0               # metres the relic is lifted above the base, in [-1, 2]
//         yaw: 0.0                  # degrees about the vertical axis, in [-360, 360]
//         duration_s: 60            # seconds on show, in [0.01, 86400]
//         turntable_deg_per_s: 10   # turning speed, degrees per second in [-360, 360]; 0: still
//         crossfade_s: 1.5          # seconds the picture blends into this relic, in [0, 60]
//       - relic: glass-vase
//
// A playlist entry that does not parse (an unknown key, a wrong type, a value out of range) does
// not fail the section: it is left out and reported in ExhibitConfig::relic_problems, so a typo in
// one entry never darkens the exhibit; loadPlaylist (installation.hpp) reports the entries whose
// files do not load the same way. A section with no entry left fails.
//
// Parsing checks every key, type and range and resolves the two paths beside the configuration
// file; it opens neither (loadInstallation in installation.hpp loads them, and fails naming the
// field when one is missing or unreadable). Kept apart from the loaders so that it links only core
// and the built-in relics, not the renderers: tests/fuzz/fuzz_config feeds it every appliance document.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/config.hpp"
#include "holo/core/plinth.hpp"

namespace holo::pipeline {

// One entry of exhibit.relics. Units: metres, degrees, seconds.
struct RelicEntryConfig {
  int index = 0;     // in exhibit.relics, from 0 (the field exhibit.relics[index])
  std::string name;  // the entry's `relic` value: the name /health and the logs give it
  // Exactly one of the two is set, as in ExhibitConfig.
  std::string builtin_relic;
  std::filesystem::path relic_file;
  bool fit_relic = false;
  std::filesystem::path panorama_file;  // resolved; empty: the section's, else the installation's hall
  std::optional<float> hall_radius_m;   // the section's when the entry names none
  std::optional<float> base_half_width_m;
  float scale = 1.0f;              // in [0.01, 100], about the relic's foot (x = z = 0, y = 0)
  float height_m = 0.0f;           // in [-1, 2]
  float yaw_deg = 0.0f;            // in [-360, 360]
  double duration_s = 60;          // in [0.01, 86400]
  double turntable_deg_per_s = 0;  // in [-360, 360]; positive: counter-clockwise seen from above
  double crossfade_s = 1.5;        // in [0, 60]
};

struct ExhibitConfig {
  // Exactly one of the two is set: a built-in relic's name (relics::relicNames()), or the glTF file
  // it names, relative paths resolved beside the configuration file (ConfigNode::pathBesideFile).
  std::string builtin_relic;
  std::filesystem::path relic_file;
  bool fit_relic = false;  // for a relic file; a built-in relic is always fitted
  // Resolved like relic_file; never empty for the single relic; for a playlist empty when the
  // section names none (each entry then needs its own, or the installation's hall serves).
  std::filesystem::path panorama_file;
  std::optional<float> hall_radius_m;    // in [0.5, 1000] metres; absent: the hall at infinity
  float base_half_width_m = 0.0f;        // in [0, 2] metres, > 0 only with hall_radius_m; 0: no base
  float camera_exposure = 1.0f;          // positive and finite
  int background_frames = 30;            // in 0..10000
  double fps = 30.0;                     // Hz, in (0, 1000]
  std::optional<PlinthSettings> plinth;  // exhibit.plinth; absent: none (every relic of a playlist)
  // The playlist, in its order, without the entries that did not parse; empty for the single
  // relic form. With a playlist, builtin_relic / relic_file / fit_relic are its first entry's.
  std::vector<RelicEntryConfig> relics;
  // Each entry left out: "entry N (NAME): why" (N = its index in exhibit.relics, from 0).
  std::vector<std::string> relic_problems;
  bool playlist() const { return !relics.empty(); }
};

// `exhibit` is the section's node (root["exhibit"]). Throws InputError naming the file and the
// field (exhibit.relic, ...) for an unknown key, a wrong type or a value out of its range, and
// for a playlist none of whose entries parses (a broken entry alone is a relic_problem).
ExhibitConfig parseExhibitConfig(const ConfigNode& exhibit);

// One playlist entry (`entry` = exhibit["relics"][index]) with the section's defaults in `section`;
// throws InputError naming exhibit.relics[index].FIELD.
RelicEntryConfig parseRelicEntry(const ConfigNode& entry, int index, const ExhibitConfig& section);

}  // namespace holo::pipeline
