// The `depthfilter:` configuration section: values reach the filter, bad ones are refused with
// the file, the field and the range.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/depthfilter/depth_filter_config.hpp"

namespace holo::depthfilter {
namespace {

TemporalDepthFilterConfig parsed(const std::string& body) {
  const ConfigNode section = ConfigNode::parse("depthfilter:\n" + body, "museum.yaml")["depthfilter"];
  parseCrossCameraFillConfig(section);
  parseForegroundMaskConfig(section);
  parseFullSizeOutline(section, parseForegroundScale(section));
  return parseDepthFilterConfig(section);
}

CrossCameraFillConfig parsedCrossCamera(const std::string& body) {
  return parseCrossCameraFillConfig(ConfigNode::parse("depthfilter:\n" + body, "museum.yaml")["depthfilter"]);
}

TEST(DepthFilterConfig, FieldsReachTheFilterAndOthersKeepTheirDefaults) {
  const TemporalDepthFilterConfig c = parsed("  levels: 5\n  fill_radius: 2\n  surface_tolerance_m: 0.05\n");
  const TemporalDepthFilterConfig defaults;
  EXPECT_EQ(c.levels, 5);
  EXPECT_EQ(c.fill_radius, 2);
  EXPECT_FLOAT_EQ(c.surface_tolerance_m, 0.05f);
  EXPECT_EQ(c.learning_frames, defaults.learning_frames);
  EXPECT_EQ(c.edge_radius, defaults.edge_radius);
  EXPECT_EQ(TemporalDepthFilter(c).config().levels, 5);
  EXPECT_TRUE(defaults.fill_mask_edge);
  EXPECT_TRUE(defaults.fill_witnessed);
  EXPECT_FALSE(parsed("  fill_witnessed: false\n").fill_witnessed);
  EXPECT_FALSE(defaults.fill_on_precursor_surface);
  const TemporalDepthFilterConfig flipped =
      parsed("  fill_mask_edge: false\n  fill_on_precursor_surface: true\n");
  EXPECT_FALSE(flipped.fill_mask_edge);
  EXPECT_TRUE(flipped.fill_on_precursor_surface);
  EXPECT_EQ(flipped.levels, defaults.levels);
}

TEST(DepthFilterConfig, CrossCameraFieldsReachTheStepAndOthersKeepTheirDefaults) {
  const CrossCameraFillConfig c =
      parsedCrossCamera("  levels: 2\n  cross_camera: true\n  cross_camera_max_splat_px: 2\n");
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.max_splat_px, 2);
  EXPECT_EQ(c.visibility_radius_px, CrossCameraFillConfig{}.visibility_radius_px);
  EXPECT_EQ(parsedCrossCamera("  levels: 2\n").enabled, CrossCameraFillConfig{}.enabled);
  EXPECT_EQ(parsed("  cross_camera_visibility_radius_px: 3\n").levels, TemporalDepthFilterConfig{}.levels);
}

TEST(DepthFilterConfig, MaskFieldsReachTheMaskAndOthersKeepTheirDefaults) {
  const ForegroundMaskConfig c = parseForegroundMaskConfig(
      ConfigNode::parse("depthfilter:\n  mask_open_radius: 2\n  mask_keep_attached_limbs: false\n"
                        "  mask_unknown_background_growth_steps: 7\n",
                        "museum.yaml")["depthfilter"]);
  EXPECT_EQ(c.open_radius, 2);
  EXPECT_EQ(c.unknown_background_growth_steps, 7);
  EXPECT_FALSE(c.keep_attached_limbs);
  EXPECT_EQ(c.close_radius, ForegroundMaskConfig{}.close_radius);
  EXPECT_TRUE(ForegroundMaskConfig{}.keep_attached_limbs);
}

TEST(DepthFilterConfig, PullPushIsOnByDefault) {
  EXPECT_GE(TemporalDepthFilterConfig{}.levels, 3);
  EXPECT_GE(parsed("  learning_frames: 10\n").levels, 3);
}

TEST(DepthFilterConfig, ForegroundScaleIsReadAndDefaultsToTheProducts) {
  const auto scale = [](const std::string& body) {
    return parseForegroundScale(ConfigNode::parse("depthfilter:\n" + body, "museum.yaml")["depthfilter"]);
  };
  EXPECT_EQ(scale("  foreground_scale: 2\n"), 2);
  EXPECT_EQ(scale("  foreground_scale: 1\n"), 1);
  EXPECT_EQ(scale("  levels: 3\n"), kDefaultForegroundScale);
}

TEST(DepthFilterConfig, FullSizeOutlineIsReadWithAReducedForegroundOnly) {
  const auto outline = [](const std::string& body) {
    const ConfigNode section = ConfigNode::parse("depthfilter:\n" + body, "museum.yaml")["depthfilter"];
    return parseFullSizeOutline(section, parseForegroundScale(section));
  };
  EXPECT_TRUE(outline("  foreground_scale: 2\n  full_size_outline: true\n"));
  EXPECT_FALSE(outline("  foreground_scale: 2\n"));
  EXPECT_FALSE(outline("  levels: 3\n"));
}

TEST(DepthFilterConfig, BadValuesAreRefusedNamingTheFieldAndTheRange) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"  levels: 0\n", "depthfilter.levels"},
      {"  levels: 9\n", "depthfilter.levels"},
      {"  levels: three\n", "depthfilter.levels"},
      {"  fill_radius: 5\n", "depthfilter.fill_radius"},
      {"  motion_window: 8\n", "depthfilter.motion_window"},
      {"  min_support: 9\n", "depthfilter.min_support"},
      {"  surface_tolerance_m: 0\n", "depthfilter.surface_tolerance_m"},
      {"  fill_colour_max: -1\n", "depthfilter.fill_colour_max"},
      {"  pull_levels: 3\n", "pull_levels"},
      {"  cross_camera: maybe\n", "depthfilter.cross_camera"},
      {"  cross_camera_max_splat_px: 0\n", "depthfilter.cross_camera_max_splat_px"},
      {"  cross_camera_visibility_radius_px: 9\n", "depthfilter.cross_camera_visibility_radius_px"},
      {"  cross_camera_tolerance_m: 0\n", "depthfilter.cross_camera_tolerance_m"},
      {"  mask_open_radius: -1\n", "depthfilter.mask_open_radius"},
      {"  mask_close_radius: 9\n", "depthfilter.mask_close_radius"},
      {"  mask_keep_attached_limbs: 2\n", "depthfilter.mask_keep_attached_limbs"},
      {"  fill_mask_edge: sometimes\n", "depthfilter.fill_mask_edge"},
      {"  fill_witnessed: perhaps\n", "depthfilter.fill_witnessed"},
      {"  fill_on_precursor_surface: 2\n", "depthfilter.fill_on_precursor_surface"},
      {"  mask_background_adopt_frames: 0\n", "depthfilter.mask_background_adopt_frames"},
      {"  mask_background_adopt_frames: 1001\n", "depthfilter.mask_background_adopt_frames"},
      {"  foreground_scale: 0\n", "depthfilter.foreground_scale"},
      {"  foreground_scale: 3\n", "depthfilter.foreground_scale"},
      {"  full_size_outline: yes please\n", "depthfilter.full_size_outline"},
      {"  foreground_scale: 1\n  full_size_outline: true\n", "depthfilter.full_size_outline"},
      {"  full_size_outline: true\n", "depthfilter.full_size_outline"},
      {"  mask_unknown_background_growth_steps: -1\n", "depthfilter.mask_unknown_background_growth_steps"},
      {"  mask_unknown_background_growth_steps: 17\n", "depthfilter.mask_unknown_background_growth_steps"},
      {"  mask_unshrunk_colour_over_unread_background: 3\n",
       "depthfilter.mask_unshrunk_colour_over_unread_background"},
  };
  for (const auto& [yaml, field] : cases) {
    try {
      parsed(yaml);
      ADD_FAILURE() << "accepted " << yaml;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.file(), "museum.yaml") << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
    }
  }
  try {
    parsed("  levels: 12\n");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[1, 8]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::depthfilter
