// The display section of a Holopyramid YAML configuration. Every field is optional; a missing
// field keeps the default of DisplayConfig (layout.hpp). Unknown fields are errors, so a typo
// never silently does nothing. Errors are InputError naming the file and the dotted field, e.g.
// "site.yaml: display.faces[2].scale (line 14): expected a number in [0.05, 20], got '0'".
//
//   display:
//     layout: cross            # monitors | cross
//     output_size: [1920, 1080]
//     fullscreen: true
//     exposure: 1.0
//     cross: {view_size: 0.3333, gap: 0.1667}
//     auto_fit: {enabled: false, margin: 0.05, threshold: 0.02}
//     faces:                   # exactly four entries when present, face 0..3
//       - {mirror: true, offset: [0, 0], scale: 1, rotation: 0, monitor: -1}
//     eyes:                    # EyeTrackerSettings (eye_tracker.hpp), same names, metres/seconds
//       {floor_y: -1.0, default_eye_height: 1.6, default_distance: 1.0, alpha: 0.35, ...}
#pragma once

#include <filesystem>

#include "holo/core/config.hpp"
#include "holo/display/eye_tracker.hpp"
#include "holo/display/layout.hpp"

namespace holo::display {

// Parses `node` (the value of the `display:` key) into a DisplayConfig.
DisplayConfig parseDisplayConfig(const ConfigNode& node);
// The `display:` section of a whole configuration document (other modules read their sections
// from the same document); a document without one gives the defaults.
DisplayConfig displayConfigOf(const ConfigNode& root);
// Reads the `display:` section of a YAML file; a file without one gives the defaults.
DisplayConfig loadDisplayConfig(const std::filesystem::path& path);
// Parses `node` (the value of `display.eyes`) into EyeTrackerSettings.
EyeTrackerSettings parseEyeTrackerSettings(const ConfigNode& node);
// Reads `display.eyes` of a YAML file; missing section or fields keep the defaults.
EyeTrackerSettings loadEyeTrackerSettings(const std::filesystem::path& path);
// `--layout monitors|cross` from the command line; `origin` names the flag in the error.
LayoutKind parseLayoutKind(const std::string& name, const std::string& origin);

}  // namespace holo::display
