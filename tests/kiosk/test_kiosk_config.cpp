#include <gtest/gtest.h>

#include "holo/core/files.hpp"
#include "holo/kiosk/kiosk_config.hpp"
#include "shared_data.hpp"

namespace holo::kiosk {
namespace {

const char* kGood = R"(kiosk:
  opening_hours: "Mon-Fri 09:00-18:00"
  max_fps: 20
  health: {address: 127.0.0.1, port: 9100, file: ""}
  degradation: {frame_budget_ms: 50, quality_levels: [a, b], down_after_frames: 4}
)";

TEST(KioskConfig, ParsesEveryField) {
  const auto c = parseKioskConfig(ConfigNode::parse(kGood, "good.yaml"));
  EXPECT_FALSE(c.opening_hours.alwaysOpen());
  EXPECT_TRUE(c.opening_hours.isOpenAt(0, 10 * 60));
  EXPECT_DOUBLE_EQ(c.max_fps, 20.0);
  EXPECT_EQ(c.health_port, 9100);
  EXPECT_TRUE(c.health_file.empty());
  EXPECT_DOUBLE_EQ(c.degradation.frame_budget_ms, 50.0);
  EXPECT_EQ(c.degradation.quality_levels, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(c.degradation.down_after_frames, 4);
  EXPECT_EQ(c.degradation.up_after_frames, DegradationSettings{}.up_after_frames);
}

TEST(KioskConfig, FactoryDefaultsEqualTheBuiltInDefaults) {
  const auto c = parseKioskConfig(ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"));
  const KioskConfig d;
  EXPECT_TRUE(c.opening_hours.alwaysOpen());
  EXPECT_EQ(c.health_port, d.health_port);
  EXPECT_EQ(c.health_file, d.health_file);
  EXPECT_DOUBLE_EQ(c.degradation.frame_budget_ms, d.degradation.frame_budget_ms);
  EXPECT_EQ(c.degradation.quality_levels, d.degradation.quality_levels);
}

TEST(KioskConfig, ThePackagedConfigurationLoads) {
  const auto path = std::filesystem::path(HOLO_SOURCE_DIR) / "packaging" / "holopyramid.yaml";
  const auto c = parseKioskConfig(ConfigNode::loadFile(path));
  EXPECT_EQ(c.health_address, "127.0.0.1");
  EXPECT_GT(c.health_port, 0);
}

TEST(KioskConfig, UnknownAndOutOfRangeFieldsAreNamed) {
  try {
    parseKioskConfig(ConfigNode::parse("kiosk:\n  helth: {}\n", "typo.yaml"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("helth"), std::string::npos) << e.what();
  }
  try {
    parseKioskConfig(ConfigNode::parse("kiosk:\n  degradation: {headroom: 3}\n", "range.yaml"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("headroom"), std::string::npos) << e.what();
  }
}

TEST(KioskConfig, GoodFileIsUsedAndKeptAsLastGood) {
  const auto dir = test::scratchDir("kiosk_config_good");
  writeFileAtomically(dir / "site.yaml", kGood);
  const auto loaded = loadConfigWithFallback(dir / "site.yaml", dir / "state" / "last-good.yaml");
  EXPECT_EQ(loaded.source, (dir / "site.yaml").string());
  EXPECT_TRUE(loaded.warning.empty());
  EXPECT_EQ(readFile(dir / "state" / "last-good.yaml"), kGood);
}

TEST(KioskConfig, CorruptFileFallsBackToLastGoodThenFactory) {
  const auto dir = test::scratchDir("kiosk_config_corrupt");
  writeFileAtomically(dir / "site.yaml", kGood);
  loadConfigWithFallback(dir / "site.yaml", dir / "last-good.yaml");
  writeFileAtomically(dir / "site.yaml", "kiosk: [unclosed\n");
  auto loaded = loadConfigWithFallback(dir / "site.yaml", dir / "last-good.yaml");
  EXPECT_NE(loaded.source.find("last good copy"), std::string::npos) << loaded.source;
  EXPECT_NE(loaded.warning.find("site.yaml"), std::string::npos) << loaded.warning;
  EXPECT_EQ(loaded.kiosk.health_port, 9100);  // the last good values, not the defaults
  // The corrupt file did not overwrite the last good copy.
  EXPECT_EQ(readFile(dir / "last-good.yaml"), kGood);

  // The last good copy is damaged too: factory defaults, and the reason names the site file.
  writeFileAtomically(dir / "last-good.yaml", "kiosk: {max_fps: -4}\n");
  loaded = loadConfigWithFallback(dir / "site.yaml", dir / "last-good.yaml");
  EXPECT_EQ(loaded.source, "factory defaults");
  EXPECT_NE(loaded.warning.find("factory defaults"), std::string::npos);
  EXPECT_EQ(loaded.kiosk.health_port, KioskConfig{}.health_port);
}

TEST(KioskConfig, ValidatorOfOtherSectionsCanRejectTheFile) {
  const auto dir = test::scratchDir("kiosk_config_validate");
  writeFileAtomically(dir / "site.yaml", "display: {layout: hexagon}\n");
  const auto loaded = loadConfigWithFallback(dir / "site.yaml", {}, [](const ConfigNode& root) {
    if (root.has("display")) root["display"]["layout"].fail("monitors or cross");
  });
  EXPECT_EQ(loaded.source, "factory defaults");
  EXPECT_NE(loaded.warning.find("display.layout"), std::string::npos) << loaded.warning;
}

}  // namespace
}  // namespace holo::kiosk
