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
//
// Parsing checks every key, type and range and resolves the two paths beside the configuration
// file; it opens neither (loadInstallation in installation.hpp loads them, and fails naming the
// field when one is missing or unreadable). Kept apart from the loaders so that it links only core
// and the built-in relics, not the renderers: tests/fuzz/fuzz_config feeds it every appliance document.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "holo/core/config.hpp"

namespace holo::pipeline {

struct ExhibitConfig {
  // Exactly one of the two is set: a built-in relic's name (relics::relicNames()), or the glTF file
  // it names, relative paths resolved beside the configuration file (ConfigNode::pathBesideFile).
  std::string builtin_relic;
  std::filesystem::path relic_file;
  bool fit_relic = false;               // for a relic file; a built-in relic is always fitted
  std::filesystem::path panorama_file;  // resolved like relic_file; never empty
  std::optional<float> hall_radius_m;   // in [0.5, 1000] metres; absent: the hall at infinity
  float base_half_width_m = 0.0f;       // in [0, 2] metres, > 0 only with hall_radius_m; 0: no base
  float camera_exposure = 1.0f;         // positive and finite
  int background_frames = 30;           // in 0..10000
  double fps = 30.0;                    // Hz, in (0, 1000]
};

// `exhibit` is the section's node (root["exhibit"]). Throws InputError naming the file and the
// field (exhibit.relic, ...) for an unknown key, a wrong type or a value out of its range.
ExhibitConfig parseExhibitConfig(const ConfigNode& exhibit);

}  // namespace holo::pipeline
