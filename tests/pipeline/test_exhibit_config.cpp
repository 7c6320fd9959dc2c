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

TEST_F(ExhibitConfigTest, PlinthIsOptionalAndItsFieldsChecked) {
  EXPECT_FALSE(parseExhibitConfig(exhibit("  relic: vase\n  panorama: hall.hdr\n")).plinth);
  const ExhibitConfig config =
      parseExhibitConfig(exhibit("  relic: vase\n  panorama: hall.hdr\n  plinth: {half_width: 0.2, height: "
                                 "0.5, gap: 0.01, albedo: [0.5, 0.6, 0.7]}\n"));
  ASSERT_TRUE(config.plinth);
  EXPECT_FLOAT_EQ(config.plinth->half_width, 0.2f);
  EXPECT_FLOAT_EQ(config.plinth->height, 0.5f);
  EXPECT_FLOAT_EQ(config.plinth->gap, 0.01f);
  EXPECT_FLOAT_EQ(config.plinth->albedo.z, 0.7f);
  const std::string base = "  relic: vase\n  panorama: hall.hdr\n  plinth: ";
  EXPECT_EQ(failingField(base + "{half_width: 0}\n"), "exhibit.plinth.half_width");
  EXPECT_EQ(failingField(base + "{height: -1}\n"), "exhibit.plinth.height");
  EXPECT_EQ(failingField(base + "{gap: 2}\n"), "exhibit.plinth.gap");
  EXPECT_EQ(failingField(base + "{albedo: [0.5, 1.5, 0.5]}\n"), "exhibit.plinth.albedo");
  EXPECT_EQ(failingField(base + "{albedo: [0.5, 0.5]}\n"), "exhibit.plinth.albedo");
  EXPECT_EQ(failingField(base + "{colour: 0.5}\n"), "exhibit.plinth.colour");
  EXPECT_EQ(failingField(base + "0.3\n"), "exhibit.plinth");
}

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

TEST_F(ExhibitConfigTest, APlaylistNamesItsRelicsWithTheSectionsDefaults) {
  const ExhibitConfig config = parseExhibitConfig(exhibit(
      "  panorama: hall.hdr\n  hall_radius: 8\n  base_half_width: 0.3\n  fit_relic: true\n"
      "  relics:\n"
      "    - relic: vase\n"
      "    - relic: relics/amphora.glb\n      panorama: /srv/other.exr\n      hall_radius: 12\n"
      "      base_half_width: 0\n      fit_relic: false\n      scale: 1.5\n      height: 0.05\n"
      "      yaw: -90\n      duration_s: 120\n      turntable_deg_per_s: -12\n      crossfade_s: 0\n"));
  ASSERT_TRUE(config.playlist());
  ASSERT_EQ(config.relics.size(), 2u);
  EXPECT_TRUE(config.relic_problems.empty());
  EXPECT_EQ(config.builtin_relic, "vase");  // the first entry's
  const RelicEntryConfig& vase = config.relics[0];
  EXPECT_EQ(vase.name, "vase");
  EXPECT_EQ(vase.index, 0);
  EXPECT_TRUE(vase.fit_relic);
  EXPECT_TRUE(vase.panorama_file.empty());  // the section's
  ASSERT_TRUE(vase.hall_radius_m);
  EXPECT_FLOAT_EQ(*vase.hall_radius_m, 8.0f);
  EXPECT_FALSE(vase.base_half_width_m);
  EXPECT_FLOAT_EQ(vase.scale, 1.0f);
  EXPECT_DOUBLE_EQ(vase.duration_s, 60.0);
  EXPECT_DOUBLE_EQ(vase.turntable_deg_per_s, 0.0);
  EXPECT_DOUBLE_EQ(vase.crossfade_s, 1.5);
  const RelicEntryConfig& amphora = config.relics[1];
  EXPECT_EQ(amphora.relic_file, dir_ / "relics/amphora.glb");
  EXPECT_FALSE(amphora.fit_relic);
  EXPECT_EQ(amphora.panorama_file, fs::path("/srv/other.exr"));
  EXPECT_FLOAT_EQ(*amphora.hall_radius_m, 12.0f);
  EXPECT_FLOAT_EQ(*amphora.base_half_width_m, 0.0f);
  EXPECT_FLOAT_EQ(amphora.scale, 1.5f);
  EXPECT_FLOAT_EQ(amphora.height_m, 0.05f);
  EXPECT_FLOAT_EQ(amphora.yaw_deg, -90.0f);
  EXPECT_DOUBLE_EQ(amphora.duration_s, 120.0);
  EXPECT_DOUBLE_EQ(amphora.turntable_deg_per_s, -12.0);
  EXPECT_DOUBLE_EQ(amphora.crossfade_s, 0.0);
  // The section needs no panorama of its own with a playlist (the installation's hall serves).
  EXPECT_TRUE(parseExhibitConfig(exhibit("  relics: [{relic: crystal}]\n")).panorama_file.empty());
}

// The field a playlist entry's problem names.
std::string entryProblem(const ExhibitConfig& config) {
  return config.relic_problems.empty() ? std::string("(no problem)") : config.relic_problems.front();
}

TEST_F(ExhibitConfigTest, ABadPlaylistEntryIsLeftOutNamingItsField) {
  const auto problem = [&](const std::string& entry) {
    const ExhibitConfig config =
        parseExhibitConfig(exhibit("  relics:\n    - relic: vase\n    - " + entry + "\n"));
    EXPECT_EQ(config.relics.size(), 1u) << entry;
    return entryProblem(config);
  };
  const auto names = [&](const std::string& entry, const std::string& field) {
    const std::string why = problem(entry);
    EXPECT_NE(why.find(field), std::string::npos) << entry << ": " << why;
    EXPECT_NE(why.find((dir_ / "appliance.yaml").string()), std::string::npos) << why;
  };
  names("{relic: crystal, duration_s: 0}", "exhibit.relics[1].duration_s");
  names("{relic: crystal, duration_s: fast}", "exhibit.relics[1].duration_s");
  names("{relic: crystal, turntable_deg_per_s: 400}", "exhibit.relics[1].turntable_deg_per_s");
  names("{relic: crystal, crossfade_s: -1}", "exhibit.relics[1].crossfade_s");
  names("{relic: crystal, crossfade_s: .nan}", "exhibit.relics[1].crossfade_s");
  names("{relic: crystal, scale: 0}", "exhibit.relics[1].scale");
  names("{relic: crystal, height: 3}", "exhibit.relics[1].height");
  names("{relic: crystal, yaw: 720}", "exhibit.relics[1].yaw");
  names("{relic: crystal, hall_radius: 0.1}", "exhibit.relics[1].hall_radius");
  names("{relic: crystal, base_half_width: 0.3}", "exhibit.relics[1].base_half_width");  // no hall
  names("{relic: crystal, panorama: ''}", "exhibit.relics[1].panorama");
  names("{relic: ''}", "exhibit.relics[1].relic");
  names("{relik: crystal}", "relik");
  names("just a name", "exhibit.relics[1]");
  EXPECT_NE(problem("{relic: crystal, scale: 0}").find("entry 1 (crystal): "), std::string::npos);
}

TEST_F(ExhibitConfigTest, APlaylistNeedsAnEntryThatParsesAndNoSingleRelicBesideIt) {
  EXPECT_EQ(failingField("  relics: []\n"), "exhibit.relics");
  EXPECT_EQ(failingField("  relics: vase\n"), "exhibit.relics");
  EXPECT_EQ(failingField("  relics: [{relic: vase, scale: -1}, {relic: ''}]\n"), "exhibit.relics");
  EXPECT_EQ(failingField("  relic: vase\n  relics: [{relic: crystal}]\n"), "exhibit.relic");
  EXPECT_EQ(failingField("  relics: [{relic: vase}]\n  base_half_width: 0.3\n"), "exhibit.base_half_width");
}

}  // namespace
}  // namespace holo::pipeline
