// The `depthfilter:` section of a configuration document: the temporal depth filter's settings
// (TemporalDepthFilterConfig, temporal_depth_filter.hpp, with the meaning and unit of each) and
// the cross-camera fill's (CrossCameraFillConfig, cross_camera_fill.hpp) and the foreground
// mask's clean-up (ForegroundMaskConfig, foreground_mask.hpp).
// Every field is optional and keeps its default when absent:
//
//   depthfilter:
//     levels: 3                     # l_max, 1..8 (1: no pull-push)
//     learning_frames: 30           # C, 0..100000
//     min_support: 2                # of the 8 neighbours, 0..8
//     motion_window: 9              # px, odd, 1..31
//     edge_radius: 2                # px, 0..8
//     fill_trust_frames: 3          # frames, 0..254
//     fill_radius: 3                # px, 0..4
//     fill_colour_max: 30           # sum of |B|,|G|,|R| differences, 0..765
//     fill_colour_margin: 20        # 0..765
//     surface_tolerance_m: 0.03     # metres, 0.001..0.5
//     surface_tolerance_z2: 0.0075  # 1/metres, 0..0.1
//     cross_camera: false                     # the cameras fill each other's holes
//     cross_camera_tolerance_m: 0.04          # metres, 0.001..0.5
//     cross_camera_tolerance_z2: 0.0075       # 1/metres, 0..0.1
//     cross_camera_visibility_radius_px: 2    # px, 0..8
//     cross_camera_max_splat_px: 3            # px, 1..8
//     cross_camera_confirm_measured: true     # agreeing measured depth joins the mask
//     mask_open_radius: 1                     # px, 0..8 (0: no opening)
//     mask_close_radius: 2                    # px, 0..8 (0: no closing)
//     mask_keep_attached_limbs: true          # regions that keep a pixel through the opening return whole
//     mask_background_adopt_frames: 30        # readings, 1..1000, before an unknown background
//                                             # depth is learned
//     mask_unshrunk_colour_over_unread_background: true  # colour before the shrink where the
//                                             # empty hall read nothing
//     mask_unknown_background_growth_steps: 8  # px, 0..16, the mask grows into readings of
//                                             # unknown background that continue its surface
//     foreground_scale: 1                     # 1..2, the foreground at the camera's size / this
//                                             (foreground_scale.hpp)
//     full_size_outline: false                # with foreground_scale 2: the outline and depth
//                                             # edges redrawn at the camera's size
//                                             # (full_size_outline.hpp); true needs scale 2
//
// An unknown field, a value of the wrong type or out of its range is a holo::InputError naming
// the file, the field (depthfilter.levels) and the range.
#pragma once

#include "holo/core/config.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"

namespace holo::depthfilter {

// `section` is root["depthfilter"]; the defaults stand for every field it does not name.
TemporalDepthFilterConfig parseDepthFilterConfig(const ConfigNode& section);
// The cross_camera* fields of the same section.
CrossCameraFillConfig parseCrossCameraFillConfig(const ConfigNode& section);
// The mask_* fields of the same section; the rest of ForegroundMaskConfig keeps its defaults.
ForegroundMaskConfig parseForegroundMaskConfig(const ConfigNode& section);
// The foreground_scale field of the same section (ForegroundPipelineConfig::scale).
int parseForegroundScale(const ConfigNode& section);
// The full_size_outline field of the same section (ForegroundPipelineConfig::full_size_outline);
// true with `scale` 1 is refused (there is no reduced outline to redraw).
bool parseFullSizeOutline(const ConfigNode& section, int scale);

}  // namespace holo::depthfilter
