// The monitors' layout as calibrated: the display step of `holopyramid calibrate` measures how
// each face's picture lands on its monitor (pyramid.yml, calib::FaceAlignment); the live loop and
// the kiosk show the faces that way. The configuration's `display.faces[f]` still overrides each
// field it sets itself (mirror, offset, scale, rotation), and only those.
//
// Conventions (calib/display_alignment.hpp and display/layout.hpp): the calibration measures the
// whole on-screen transform of the face view (rotation counter-clockwise on screen, offset in
// pixels of the calibrated face view, +y down); the display settings hold the rotation
// clockwise on top of the layout's own turn of that face, and the offset in view sides in the
// view's frame (+y up). Both mirror left-right before rotating, and scale about the centre; the
// display fits a tilted face's bounding box into its view, so the scale is corrected for the tilt
// (exact for the live loop's square face views).
#pragma once

#include <optional>

#include "holo/calib/calibration_io.hpp"
#include "holo/core/config.hpp"
#include "holo/display/layout.hpp"

namespace holo::pipeline {

// The display settings of face `face` that place it as `alignment` (measured in `pyramid`'s face
// view) does, under `layout`. The monitor stays the default.
display::FaceSettings faceSettingsFromCalibration(const calib::FaceAlignment& alignment,
                                                  const calib::PyramidCalibration& pyramid,
                                                  display::LayoutKind layout, int face);

// `config` (parsed from `root`, the whole document) with `pyramid`'s alignment applied to every
// face field that the document's display.faces[f] does not set.
display::DisplayConfig applyCalibratedFaces(display::DisplayConfig config, const ConfigNode& root,
                                            const calib::PyramidCalibration& pyramid);

// The display settings of a configuration document: its `display:` section, with the face
// alignment of capture.calibration_dir/pyramid.yml applied when the document names cameras and
// that file exists. `layout` (a command line's --layout) replaces the document's layout first, so
// the faces' rotations are taken relative to the layout that is shown. InputError (naming the
// file and field) for a broken pyramid.yml.
display::DisplayConfig calibratedDisplayConfig(const ConfigNode& root,
                                               std::optional<display::LayoutKind> layout = std::nullopt);

}  // namespace holo::pipeline
