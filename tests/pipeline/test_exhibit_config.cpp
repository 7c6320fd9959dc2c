// The exhibit: section is parsed without its files: the relic and the panorama it names need not
// exist until loadInstallation loads them, relative paths resolve beside the configuration file,
// and every bad field is an InputError naming the file and exhibit.FIELD.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "holo/core/error.hpp"
#include "holo/pipeline/exhibit_config.hpp"

namespace holo::pipeline {
namespace {

namespace fs = std::filesystem;

class ExhibitConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("holo_exhibit_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  // The document as an existing file, so that its relative paths resolve beside it.
  ConfigNode exhibit(const std::string& section) const {
    const fs::path file = dir_ / "appliance.yaml";
    std::ofstream(file) << "exhibit:\n" << section;
    return ConfigNode::loadFile(file)["exhibit"];
  }
  // The field an error names, without the line ConfigNode adds (a parse that succeeds fails the
  // test).
  std::string failingField(const std::string& section) const {
    try {
      (void)parseExhibitConfig(exhibit(section));
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (dir_ / "appliance.yaml").string()) << e.what();
      return e.field().substr(0, e.field().find(" (line "));
    }
    ADD_FAILURE() << "accepted:\n" << section;
    return {};
  }
  fs::path dir_;
};

TEST_F(ExhibitConfigTest, FilesAreNamedBesideTheConfigurationWithoutBeingOpened) {
  const ExhibitConfig config = parseExhibitConfig(
      exhibit("  relic: relics/amphora.glb\n  fit_relic: true\n  panorama: /srv/hall.exr\n"
              "  hall_radius: 8.5\n  base_half_width: 0.35\n  camera_exposure: 0.8\n  background_frames: 0\n"
              "  fps: 29.97\n"));
  EXPECT_TRUE(config.builtin_relic.empty());
  EXPECT_EQ(config.relic_file, dir_ / "relics/amphora.glb");  // does not exist
  EXPECT_TRUE(config.fit_relic);
  EXPECT_EQ(config.panorama_file, fs::path("/srv/hall.exr"));
  ASSERT_TRUE(config.hall_radius_m);
  EXPECT_FLOAT_EQ(*config.hall_radius_m, 8.5f);
  EXPECT_FLOAT_EQ(config.base_half_width_m, 0.35f);
  EXPECT_FLOAT_EQ(config.camera_exposure, 0.8f);
  EXPECT_EQ(config.background_frames, 0);
  EXPECT_DOUBLE_EQ(config.fps, 29.97);
}

TEST_F(ExhibitConfigTest, ABuiltInRelicNamesNoFileAndDefaultsFillTheRest) {
  const ExhibitConfig config = parseExhibitConfig(exhibit("  relic: crystal\n  panorama: hall.hdr\n"));
  EXPECT_EQ(config.builtin_relic, "crystal");
  EXPECT_TRUE(config.relic_file.empty());
  EXPECT_EQ(config.panorama_file, dir_ / "hall.hdr");
  EXPECT_FALSE(config.hall_radius_m);
  EXPECT_EQ(config.base_half_width_m, 0.0f);
  EXPECT_FLOAT_EQ(config.camera_exposure, 1.0f);
  EXPECT_EQ(config.background_frames, 30);
  EXPECT_DOUBLE_EQ(config.fps, 30.0);
}

TEST_F(ExhibitConfigTest, EveryBadFieldIsNamed) {
  const std::string ok = "  relic: vase\n  panorama: hall.hdr\n";
  EXPECT_EQ(failingField("  panorama: hall.hdr\n"), "exhibit.relic");
  EXPECT_EQ(failingField("  relic: ''\n  panorama: hall.hdr\n"), "exhibit.relic");
  EXPECT_EQ(failingField("  relic: [a, b]\n  panorama: hall.hdr\n"), "exhibit.relic");
  EXPECT_EQ(failingField("  relic: vase\n"), "exhibit.panorama");
  EXPECT_EQ(failingField("  relic: vase\n  panorama: ''\n"), "exhibit.panorama");
  EXPECT_EQ(failingField(ok + "  fit_relic: maybe\n"), "exhibit.fit_relic");
  EXPECT_EQ(failingField(ok + "  hall_radius: 0.4\n"), "exhibit.hall_radius");
  EXPECT_EQ(failingField(ok + "  hall_radius: .nan\n"), "exhibit.hall_radius");
  const std::string hall = ok + "  hall_radius: 8\n";
  EXPECT_EQ(failingField(hall + "  base_half_width: -0.1\n"), "exhibit.base_half_width");
  EXPECT_EQ(failingField(hall + "  base_half_width: .nan\n"), "exhibit.base_half_width");
  EXPECT_EQ(failingField(hall + "  base_half_width: 2.5\n"), "exhibit.base_half_width");
  EXPECT_EQ(failingField(hall + "  base_half_width: wide\n"), "exhibit.base_half_width");
  EXPECT_EQ(failingField(ok + "  base_half_width: 0.3\n"), "exhibit.base_half_width");  // no hall_radius
  EXPECT_EQ(parseExhibitConfig(exhibit(ok + "  base_half_width: 0\n")).base_half_width_m, 0.0f);
  EXPECT_EQ(failingField(ok + "  camera_exposure: 0\n"), "exhibit.camera_exposure");
  EXPECT_EQ(failingField(ok + "  camera_exposure: 1e39\n"), "exhibit.camera_exposure");  // inf as float
  EXPECT_EQ(failingField(ok + "  background_frames: 10001\n"), "exhibit.background_frames");
  EXPECT_EQ(failingField(ok + "  fps: 0\n"), "exhibit.fps");
  const std::string typo = failingField(ok + "  hall_raduis: 8\n");
  EXPECT_NE(typo.find("hall_raduis"), std::string::npos) << typo;
}

}  // namespace
}  // namespace holo::pipeline
