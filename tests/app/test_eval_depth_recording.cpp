// `holopyramid eval depth --recording DIR`: the depth filter on a recording without truth, as a
// user would run it on a real one: a short `holopyramid simulate` recording (with its background
// frames), the same camera as a plain TUM RGB-D sequence folder (5000 units per metre, no
// background: the first frames stand in), and a single frame, which has nothing to compare.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "command_output.hpp"
#include "run_holopyramid.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using holo::test::logText;
using holo::test::readJson;

void expectShare(const nlohmann::json& value, const std::string& what) {
  ASSERT_TRUE(value.is_number()) << what << " = " << value.dump();
  EXPECT_GE(value.get<double>(), 0.0) << what;
  EXPECT_LE(value.get<double>(), 1.0) << what;
}

// cam0 of a holopyramid recording rewritten as TUM publishes a sequence: rgb/, depth/ at 5000
// units per metre, rgb.txt and depth.txt (no associations.txt: readRecording pairs them).
void writeTumSequence(const fs::path& camera, const fs::path& out) {
  fs::create_directories(out / "rgb");
  fs::create_directories(out / "depth");
  fs::copy_file(camera / "rgb.txt", out / "rgb.txt");
  fs::copy_file(camera / "depth.txt", out / "depth.txt");
  for (const auto& entry : fs::directory_iterator(camera / "rgb"))
    fs::copy_file(entry.path(), out / "rgb" / entry.path().filename());
  for (const auto& entry : fs::directory_iterator(camera / "depth")) {
    const cv::Mat millimetres = cv::imread(entry.path().string(), cv::IMREAD_ANYDEPTH);
    ASSERT_EQ(millimetres.type(), CV_16UC1);
    cv::Mat tum;
    millimetres.convertTo(tum, CV_16UC1, 5.0);  // 1000 -> 5000 units per metre (simulated depth < 13 m)
    ASSERT_TRUE(cv::imwrite((out / "depth" / entry.path().filename()).string(), tum));
  }
}

TEST(EvalDepthRecording, MeasuresASimulatedRecordingATumSequenceAndRefusesOneFrame) {
  const fs::path dir = holo::test::scratchDir("eval_depth_recording");
  std::ofstream(dir / "small.yaml") << "base: museum\ncamera: {width: 320, height: 180}\n";
  ASSERT_EQ(
      holo::test::runHolopyramid("simulate --scene " + (dir / "small.yaml").string() +
                                     " --frames 24 --panorama-width 64 -q --out " + (dir / "rec").string(),
                                 dir / "simulate.txt"),
      0)
      << logText(dir / "simulate.txt");

  // The recording with its background frames.
  const int rc = holo::test::runHolopyramid("eval depth --recording " + (dir / "rec").string() +
                                                " --learning-frames 4 --json " + (dir / "rec.json").string() +
                                                " --images " + (dir / "images").string(),
                                            dir / "rec.txt");
  ASSERT_EQ(rc, 0) << logText(dir / "rec.txt");
  const nlohmann::json r = readJson(dir / "rec.json");
  EXPECT_EQ(r.at("layout"), "holopyramid");
  EXPECT_EQ(r.at("background"), "recorded");
  EXPECT_EQ(r.at("cameras"), 4);
  EXPECT_GT(r.at("frame_pairs").get<int>(), 40);  // 4 cameras x 20 (measured 80)
  for (const char* stream : {"raw", "filtered"}) {
    const auto& f = r.at("foreground").at(stream);
    expectShare(f.at("hole_flicker"), stream);
    EXPECT_GT(f.at("pixel_pairs").get<long long>(), 10000) << stream;
    EXPECT_GT(f.at("edge_jitter_px").get<double>(), 0.0) << stream;
  }
  // The filter fills holes on the visitors: its output flickers less than the sensor's depth
  // (measured 0.044 against 0.061) and its edges jitter less (0.73 against 0.99 px).
  EXPECT_LT(r.at("foreground").at("filtered").at("hole_flicker").get<double>(),
            r.at("foreground").at("raw").at("hole_flicker").get<double>());
  EXPECT_LT(r.at("foreground").at("filtered").at("edge_jitter_px").get<double>(),
            r.at("foreground").at("raw").at("edge_jitter_px").get<double>());
  expectShare(r.at("background_raw").at("hole_flicker"), "background");
  // The structured-light profile's noise at 2 m is 3.6 mm (sigma) and its quantisation step 5.7
  // mm: the still background's per-pixel spread there is a few millimetres (measured 4.2).
  const double at_2m = r.at("background_noise_mm_at").at("2m").get<double>();
  EXPECT_GT(at_2m, 1.0);
  EXPECT_LT(at_2m, 10.0);
  EXPECT_TRUE(fs::exists(dir / "images" / "depth_stability.png"));

  // The same camera as a TUM sequence, the first 4 frames taken as the empty room.
  writeTumSequence(dir / "rec" / "cam0", dir / "tum");
  ASSERT_EQ(holo::test::runHolopyramid("eval depth --recording " + (dir / "tum").string() +
                                           " --background-frames 4 --learning-frames 4 --json " +
                                           (dir / "tum.json").string(),
                                       dir / "tum.txt"),
            0)
      << logText(dir / "tum.txt");
  const nlohmann::json t = readJson(dir / "tum.json");
  EXPECT_EQ(t.at("layout"), "tum-sequence");
  EXPECT_EQ(t.at("background"), "first 4 frames");
  EXPECT_EQ(t.at("cameras"), 1);
  // The filter learns until its PDFs hold enough foreground samples, which a visitor standing in
  // the first frames (taken as the empty room) delays: measured 11 of 15 possible pairs.
  EXPECT_GT(t.at("frame_pairs").get<int>(), 8);
  expectShare(t.at("foreground").at("raw").at("hole_flicker"), "tum raw");
  // Depth read at TUM's scale: the background's spread stays millimetres, not 5x off.
  EXPECT_LT(t.at("background_noise_mm").get<double>(), 20.0);
  EXPECT_GT(t.at("background_noise_mm").get<double>(), 0.5);

  // One frame (the layout of ../shared/data/rgbd/tum_walking) has nothing to compare.
  fs::create_directories(dir / "single");
  fs::copy_file(dir / "rec" / "cam0" / "rgb" / "000000.png", dir / "single" / "color.png");
  fs::copy_file(dir / "tum" / "depth" / "000000.png", dir / "single" / "depth.png");
  EXPECT_NE(
      holo::test::runHolopyramid("eval depth --recording " + (dir / "single").string(), dir / "single.txt"),
      0);
  EXPECT_NE(logText(dir / "single.txt").find("a sequence of at least"), std::string::npos)
      << logText(dir / "single.txt");

  // Bad counts name the option.
  for (const std::string option : {"--learning-frames", "--background-frames"}) {
    EXPECT_NE(holo::test::runHolopyramid(
                  "eval depth --recording " + (dir / "tum").string() + " " + option + " -1", dir / "bad.txt"),
              0);
    EXPECT_NE(logText(dir / "bad.txt").find(option), std::string::npos) << logText(dir / "bad.txt");
  }
}

}  // namespace
