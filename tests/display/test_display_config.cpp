// The display section of the YAML configuration: values land, bad input names file and field.
#include <gtest/gtest.h>

#include <fstream>

#include "holo/core/error.hpp"
#include "holo/display/display_config.hpp"
#include "shared_data.hpp"

namespace holo::display {
namespace {

std::filesystem::path writeYaml(const std::string& name, const std::string& text) {
  const auto path = test::scratchDir("display_config_" + name) / (name + ".yaml");
  std::ofstream(path) << text;
  return path;
}

// The InputError's message, which must name the file and the dotted field.
std::string errorOf(const std::filesystem::path& path) {
  try {
    loadDisplayConfig(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(DisplayConfig, ReadsEveryField) {
  const auto path = writeYaml("full", R"(
display:
  layout: monitors
  output_size: [640, 480]
  fullscreen: false
  exposure: 2.5
  cross: {view_size: 0.3, gap: 0.1}
  auto_fit: {enabled: true, margin: 0.1, threshold: 0.05}
  faces:
    - {mirror: false, offset: [0.1, -0.2], scale: 1.5, rotation: 90, monitor: 2}
    - {}
    - {mirror: true}
    - {rotation: -45}
)");
  const DisplayConfig config = loadDisplayConfig(path);
  EXPECT_EQ(config.layout, LayoutKind::Monitors);
  EXPECT_EQ(config.output_size, cv::Size(640, 480));
  EXPECT_FALSE(config.fullscreen);
  EXPECT_FLOAT_EQ(config.exposure, 2.5f);
  EXPECT_FLOAT_EQ(config.cross_view_size, 0.3f);
  EXPECT_FLOAT_EQ(config.cross_gap, 0.1f);
  EXPECT_TRUE(config.auto_fit.enabled);
  EXPECT_FLOAT_EQ(config.auto_fit.margin, 0.1f);
  EXPECT_FALSE(config.faces[0].mirror);
  EXPECT_FLOAT_EQ(config.faces[0].offset.y, -0.2f);
  EXPECT_FLOAT_EQ(config.faces[0].scale, 1.5f);
  EXPECT_FLOAT_EQ(config.faces[0].rotation_deg, 90.0f);
  EXPECT_EQ(config.faces[0].monitor, 2);
  EXPECT_TRUE(config.faces[1].mirror);  // default kept
  EXPECT_FLOAT_EQ(config.faces[3].rotation_deg, -45.0f);
  EXPECT_EQ(config.source, path.string());
}

TEST(DisplayConfig, FileWithoutDisplaySectionGivesDefaults) {
  const DisplayConfig config = loadDisplayConfig(writeYaml("other", "capture: {cameras: 4}\n"));
  EXPECT_EQ(config.layout, LayoutKind::Cross);
  EXPECT_EQ(config.output_size, cv::Size(1920, 1080));  // a Full HD screen
}

struct BadCase {
  const char* name;
  const char* yaml;
  const char* field;     // must appear in the message
  const char* expected;  // a phrase of the expectation
};

class BadDisplayConfig : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadDisplayConfig, InputErrorNamesFileAndField) {
  const BadCase& c = GetParam();
  const auto path = writeYaml(c.name, c.yaml);
  const std::string message = errorOf(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find(c.field), std::string::npos) << message;
  EXPECT_NE(message.find(c.expected), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Fields, BadDisplayConfig,
    ::testing::Values(
        BadCase{"layout", "display: {layout: diagonal}\n", "display.layout", "monitors or cross"},
        BadCase{"size", "display: {output_size: [640]}\n", "display.output_size", "[width, height]"},
        BadCase{"tiny", "display: {output_size: [8, 8]}\n", "display.output_size", "16 and 16384"},
        BadCase{"three_faces", "display: {faces: [{}, {}, {}]}\n", "display.faces", "exactly 4"},
        BadCase{"scale", "display: {faces: [{}, {}, {scale: 0}, {}]}\n", "display.faces[2].scale", "0.05"},
        BadCase{"mirror", "display: {faces: [{mirror: maybe}, {}, {}, {}]}\n", "display.faces[0].mirror",
                "true or false"},
        BadCase{"typo", "display: {layuot: cross}\n", "display.layuot", "one of the fields"},
        BadCase{"cross", "display: {cross: {view_size: 0.4, gap: 0.3}}\n", "display.cross",
                "view_size + gap"},
        BadCase{"nan", "display: {exposure: .nan}\n", "display.exposure", "finite"}),
    [](const ::testing::TestParamInfo<BadCase>& param) { return std::string(param.param.name); });

TEST(DisplayConfig, EyeTrackerSettingsFromTheEyesSection) {
  const auto path = writeYaml("eyes", R"(
display:
  layout: cross
  eyes: {floor_y: -1.2, default_eye_height: 1.5, alpha: 0.6, lost_timeout_s: 2.5, min_support: 30}
)");
  const EyeTrackerSettings eyes = loadEyeTrackerSettings(path);
  EXPECT_FLOAT_EQ(eyes.floor_y, -1.2f);
  EXPECT_FLOAT_EQ(eyes.default_eye_height, 1.5f);
  EXPECT_FLOAT_EQ(eyes.alpha, 0.6f);
  EXPECT_DOUBLE_EQ(eyes.lost_timeout_s, 2.5);
  EXPECT_EQ(eyes.min_support, 30);
  EXPECT_FLOAT_EQ(eyes.beta, EyeTrackerSettings{}.beta);         // default kept
  EXPECT_EQ(loadDisplayConfig(path).layout, LayoutKind::Cross);  // the display parser accepts it
  EXPECT_FLOAT_EQ(loadEyeTrackerSettings(writeYaml("no_eyes", "display: {layout: cross}\n")).alpha,
                  EyeTrackerSettings{}.alpha);

  const auto bad = writeYaml("bad_eyes", "display:\n  eyes: {alpha: 0}\n");
  try {
    loadEyeTrackerSettings(bad);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(bad.string()), std::string::npos) << message;
    EXPECT_NE(message.find("display.eyes.alpha"), std::string::npos) << message;
  }
  const auto crossed =
      writeYaml("crossed_eyes", "display:\n  eyes: {min_head_top: 2.0, max_head_top: 1.5}\n");
  EXPECT_THROW(loadEyeTrackerSettings(crossed), InputError);
}

TEST(DisplayConfig, LayoutFlagErrorNamesTheFlag) {
  EXPECT_EQ(parseLayoutKind("cross", "command line"), LayoutKind::Cross);
  try {
    parseLayoutKind("triangle", "command line");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--layout");
    EXPECT_NE(std::string(e.what()).find("monitors or cross"), std::string::npos);
  }
}

}  // namespace
}  // namespace holo::display
