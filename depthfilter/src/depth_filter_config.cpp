#include "holo/depthfilter/depth_filter_config.hpp"

#include <string>

#include "holo/depthfilter/mask_depth_growth.hpp"

namespace holo::depthfilter {
namespace {

// An integer field in [lo, hi]; the error names the range.
int intInRange(const ConfigNode& section, const std::string& key, int fallback, int lo, int hi) {
  if (!section.has(key)) return fallback;
  const ConfigNode child = section[key];
  const int value = child.as<int>();
  if (value < lo || value > hi)
    child.fail("an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
               std::to_string(value));
  return value;
}

}  // namespace

TemporalDepthFilterConfig parseDepthFilterConfig(const ConfigNode& section) {
  section.rejectUnknownKeys({"levels",
                             "learning_frames",
                             "min_support",
                             "motion_window",
                             "edge_radius",
                             "fill_trust_frames",
                             "fill_on_precursor_surface",
                             "fill_mask_edge",
                             "fill_witnessed",
                             "fill_radius",
                             "fill_colour_max",
                             "fill_colour_margin",
                             "surface_tolerance_m",
                             "surface_tolerance_z2",
                             "cross_camera",
                             "cross_camera_tolerance_m",
                             "cross_camera_tolerance_z2",
                             "cross_camera_visibility_radius_px",
                             "cross_camera_max_splat_px",
                             "cross_camera_confirm_measured",
                             "mask_open_radius",
                             "mask_close_radius",
                             "mask_keep_attached_limbs",
                             "mask_background_adopt_frames",
                             "mask_unshrunk_colour_over_unread_background",
                             "mask_unknown_background_growth_steps",
                             "foreground_scale",
                             "full_size_outline"});
  TemporalDepthFilterConfig c;
  c.levels = intInRange(section, "levels", c.levels, 1, TemporalDepthFilterConfig::kMaxLevels);
  c.learning_frames = intInRange(section, "learning_frames", c.learning_frames, 0, 100000);
  c.min_support = intInRange(section, "min_support", c.min_support, 0, 8);
  c.motion_window = intInRange(section, "motion_window", c.motion_window, 1, 31);
  if (c.motion_window % 2 == 0)
    section["motion_window"].fail("an odd integer in [1, 31] (a window centred on the pixel)",
                                  std::to_string(c.motion_window));
  c.edge_radius = intInRange(section, "edge_radius", c.edge_radius, 0, 8);
  c.fill_trust_frames = intInRange(section, "fill_trust_frames", c.fill_trust_frames, 0, 254);
  c.fill_on_precursor_surface = section.get("fill_on_precursor_surface", c.fill_on_precursor_surface);
  c.fill_mask_edge = section.get("fill_mask_edge", c.fill_mask_edge);
  c.fill_witnessed = section.get("fill_witnessed", c.fill_witnessed);
  c.fill_radius =
      intInRange(section, "fill_radius", c.fill_radius, 0, TemporalDepthFilterConfig::kMaxFillRadius);
  c.fill_colour_max = section.getInRange("fill_colour_max", c.fill_colour_max, 0.0f, 765.0f);
  c.fill_colour_margin = section.getInRange("fill_colour_margin", c.fill_colour_margin, 0.0f, 765.0f);
  c.surface_tolerance_m = section.getInRange("surface_tolerance_m", c.surface_tolerance_m, 0.001f, 0.5f);
  c.surface_tolerance_z2 = section.getInRange("surface_tolerance_z2", c.surface_tolerance_z2, 0.0f, 0.1f);
  return c;
}

CrossCameraFillConfig parseCrossCameraFillConfig(const ConfigNode& section) {
  CrossCameraFillConfig c;
  c.enabled = section.get("cross_camera", c.enabled);
  c.tolerance_m = section.getInRange("cross_camera_tolerance_m", c.tolerance_m, 0.001f, 0.5f);
  c.tolerance_z2 = section.getInRange("cross_camera_tolerance_z2", c.tolerance_z2, 0.0f, 0.1f);
  c.visibility_radius_px =
      intInRange(section, "cross_camera_visibility_radius_px", c.visibility_radius_px, 0, 8);
  c.max_splat_px = intInRange(section, "cross_camera_max_splat_px", c.max_splat_px, 1, 8);
  c.confirm_measured = section.get("cross_camera_confirm_measured", c.confirm_measured);
  return c;
}

ForegroundMaskConfig parseForegroundMaskConfig(const ConfigNode& section) {
  ForegroundMaskConfig c;
  c.open_radius = intInRange(section, "mask_open_radius", c.open_radius, 0, 8);
  c.close_radius = intInRange(section, "mask_close_radius", c.close_radius, 0, 8);
  c.keep_attached_limbs = section.get("mask_keep_attached_limbs", c.keep_attached_limbs);
  c.background_adopt_frames = intInRange(section, "mask_background_adopt_frames", c.background_adopt_frames,
                                         1, ForegroundMaskConfig::kMaxBackgroundAdoptFrames);
  c.unshrunk_colour_over_unread_background =
      section.get("mask_unshrunk_colour_over_unread_background", c.unshrunk_colour_over_unread_background);
  c.unknown_background_growth_steps =
      intInRange(section, "mask_unknown_background_growth_steps", c.unknown_background_growth_steps, 0,
                 MaskDepthGrowthConfig::kMaxSteps);
  return c;
}

int parseForegroundScale(const ConfigNode& section) {
  return intInRange(section, "foreground_scale", kDefaultForegroundScale, 1, kMaxForegroundScale);
}

bool parseFullSizeOutline(const ConfigNode& section, int scale) {
  const bool full_size_outline = section.get("full_size_outline", false);
  if (full_size_outline && scale == 1)
    section["full_size_outline"].fail(
        "false with foreground_scale 1 (it redraws a reduced foreground's outline)", "true");
  return full_size_outline;
}

}  // namespace holo::depthfilter
