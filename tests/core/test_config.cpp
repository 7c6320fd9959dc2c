#include <gtest/gtest.h>
#include <fstream>

#include "holo/core/config.hpp"
#include "holo/core/files.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Config, ReadsNestedValues) {
  const auto c =
      ConfigNode::parse("camera:\n  fov: [110, 70]\n  pos: [1, 2.5, -3]\n  name: left\n", "inline");
  EXPECT_EQ(c["camera"]["fov"].as<vec2>(), vec2(110, 70));
  EXPECT_EQ(c["camera"]["pos"].as<vec3>(), vec3(1, 2.5f, -3));
  EXPECT_EQ(c["camera"]["name"].as<std::string>(), "left");
  EXPECT_EQ(c["camera"].get<int>("missing", 4), 4);
}

TEST(Config, ErrorsNameFileFieldAndExpectation) {
  const auto c = ConfigNode::parse("cameras:\n  - pos: [1, 2]\n    fps: fast\n", "museum.yaml");
  const std::string wrong_size = errorOf([&] { c["cameras"][0]["pos"].as<vec3>(); });
  EXPECT_NE(wrong_size.find("museum.yaml"), std::string::npos) << wrong_size;
  EXPECT_NE(wrong_size.find("cameras[0].pos"), std::string::npos) << wrong_size;
  EXPECT_NE(wrong_size.find("3 numbers"), std::string::npos) << wrong_size;
  const std::string not_number = errorOf([&] { c["cameras"][0]["fps"].as<float>(); });
  EXPECT_NE(not_number.find("cameras[0].fps"), std::string::npos) << not_number;
  EXPECT_NE(not_number.find("'fast'"), std::string::npos) << not_number;
  EXPECT_NE(errorOf([&] { c["lights"]; }).find("lights"), std::string::npos);
  EXPECT_NE(errorOf([&] { c["cameras"][3]; }).find("cameras[3]"), std::string::npos);
}

TEST(Config, RangeCheckedValues) {
  const auto c = ConfigNode::parse("roughness: 1.5\n", "m.yaml");
  const std::string e = errorOf([&] { c.getInRange("roughness", 0.5f, 0.0f, 1.0f); });
  EXPECT_NE(e.find("[0, 1]"), std::string::npos) << e;
}

TEST(Config, SyntaxErrorGivesLine) {
  const auto dir = test::scratchDir("config_syntax");
  std::ofstream(dir / "bad.yaml") << "a: 1\nb: [1, 2\n";
  const std::string e = errorOf([&] { ConfigNode::loadFile(dir / "bad.yaml"); });
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("line"), std::string::npos) << e;
  EXPECT_NE(errorOf([&] { ConfigNode::loadFile(dir / "absent.yaml"); }).find("absent.yaml"),
            std::string::npos);
}

TEST(Config, UnknownKeysAreErrorsThatListTheKnownOnes) {
  const auto c = ConfigNode::parse("exhibit:\n  relic: vase\n  panaroma: hall.hdr\nlist: [1]\n", "cfg.yaml");
  const std::string typo = errorOf([&] { c["exhibit"].rejectUnknownKeys({"relic", "panorama"}); });
  EXPECT_NE(typo.find("exhibit.panaroma"), std::string::npos) << typo;
  EXPECT_NE(typo.find("relic, panorama"), std::string::npos) << typo;
  EXPECT_EQ(errorOf([&] { c["exhibit"].rejectUnknownKeys({"relic", "panaroma"}); }), "(no error)");
  const std::string not_map = errorOf([&] { c["list"].rejectUnknownKeys({"a"}); });
  EXPECT_NE(not_map.find("a map"), std::string::npos) << not_map;
}

// YAML lets any node be a key ("? [a, b]"): a configuration's keys are names, and anything else
// is an InputError naming the map (fuzz_config found it escaping as a YAML exception).
TEST(Config, AKeyThatIsNotANameIsAnInputError) {
  const auto c = ConfigNode::parse("capture:\n  face: 3\n  ? [backend, sim]\n  : x\n", "capture.yaml");
  const std::string error = errorOf([&] { c["capture"].rejectUnknownKeys({"face"}); });
  EXPECT_NE(error.find("capture.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("keys are names"), std::string::npos) << error;
}

TEST(Config, RelativePathsAreBesideTheFile) {
  const auto dir = test::scratchDir("config_paths");
  std::ofstream(dir / "cfg.yaml") << "recording: rec\n";
  const auto c = ConfigNode::loadFile(dir / "cfg.yaml");
  EXPECT_EQ(c.pathBesideFile("rec"), dir / "rec");
  EXPECT_EQ(c.pathBesideFile("/abs/rec"), std::filesystem::path("/abs/rec"));
  // Text that came from no file (embedded defaults) keeps paths as written.
  EXPECT_EQ(ConfigNode::parse("a: 1\n", "factory defaults").pathBesideFile("rec"),
            std::filesystem::path("rec"));
}

TEST(Files, AtomicWriteReplacesWholeFileAndLeavesNoTemporary) {
  const auto dir = test::scratchDir("atomic");
  writeFileAtomically(dir / "a.txt", "first");
  writeFileAtomically(dir / "a.txt", "second version");
  EXPECT_EQ(readFile(dir / "a.txt"), "second version");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(Files, FailedWriteKeepsPreviousFile) {
  const auto dir = test::scratchDir("atomic_fail");
  writeFileAtomically(dir / "calib.yml", "good");
  EXPECT_THROW(writeAtomically(dir / "calib.yml",
                               [](const std::filesystem::path& tmp) {
                                 std::ofstream(tmp) << "half";
                                 throw Error("interrupted");
                               }),
               Error);
  EXPECT_EQ(readFile(dir / "calib.yml"), "good");
}

}  // namespace
}  // namespace holo
