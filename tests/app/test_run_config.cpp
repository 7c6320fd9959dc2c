// `holopyramid run --config FILE` on configured cameras, as a user runs it: a recording made with
// the capture module's Recorder (the simulated museum at a small camera size: a few frames of the
// empty hall, then visitors), a relic saved as glTF, a panorama saved as EXR, a calibration folder
// with camera files for some cameras and a pyramid file. Checks that the run used those cameras
// (four live in every frame, foreground points once visitors come), stopped when the recording
// ended, and that bad configurations fail with the file and the field named; the kiosk runs the
// same configuration.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "holo/calib/calibration_io.hpp"
#include "holo/capture/recorder.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/sim/museum.hpp"
#include "run_holopyramid.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;

using holo::test::runHolopyramid;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

constexpr int kBackgroundFrames = 4;  // the empty hall, before the visitors come
constexpr int kVisitorFrames = 8;

// The folder every test here shares, made once: recording, relic, panorama, calibration.
class RunConfig : public ::testing::Test {
 protected:
  // ctest runs each test in its own process, several at once: each process makes its own folder.
  static void SetUpTestSuite() {
    dir_ = new fs::path(holo::test::scratchDir("app_run_config_" + std::to_string(getpid())));
    const fs::path& dir = *dir_;
    writeText(dir / "small_museum.yaml",
              "base: museum\ncamera: {width: 160, height: 96, hfov_deg: 110, vfov_deg: 70, fps: 30}\n");
    const holo::sim::Museum museum(holo::sim::loadScene((dir / "small_museum.yaml").string()));
    exposure_ = museum.description().camera.exposure;

    std::vector<holo::capture::RecorderCamera> cameras;
    for (int i = 0; i < museum.cameraCount(); ++i)
      cameras.push_back({"cam" + std::to_string(i), "REC-" + std::to_string(i), museum.camera(i)});
    {
      holo::capture::Recorder recorder(dir / "recording", cameras);
      for (int k = 0; k < kBackgroundFrames + kVisitorFrames; ++k)
        for (int i = 0; i < museum.cameraCount(); ++i) {
          holo::RgbdFrame frame = museum.renderCamera(i, k, k >= kBackgroundFrames).frame;
          frame.camera_id = i;
          frame.device_time = holo::Nanoseconds(static_cast<std::int64_t>(k * 1e9 / 30.0));
          recorder.write(frame);
        }
      recorder.finish();
    }
    holo::saveGltf(dir / "relic.glb", museum.relic());
    holo::saveHdr(dir / "hall.exr", museum.renderPanorama(128, 64));
    // Cameras 0 and 1 calibrated (their true models); 2 and 3 keep the recording's.
    fs::create_directories(dir / "calibration");
    for (int i = 0; i < 2; ++i)
      holo::calib::saveCameraCalibration(
          holo::calib::cameraCalibrationPath(dir / "calibration", "REC-" + std::to_string(i)),
          holo::calib::fromCameraModel(museum.camera(i), "REC-" + std::to_string(i)));
    holo::calib::PyramidCalibration pyramid;
    pyramid.panorama_yaw_rad = 0.25f;
    holo::calib::savePyramidCalibration(holo::calib::pyramidCalibrationPath(dir / "calibration"), pyramid);
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
  }

  // A configuration with `exhibit` as its exhibit: section body (indented by 2).
  // `last_camera`: which camera of the recording face 3 shows (3 unless a test breaks it).
  static fs::path writeConfig(const std::string& name, const std::string& exhibit, int last_camera = 3) {
    std::string text = "capture:\n  calibration_dir: calibration\n  cameras:\n";
    for (int i = 0; i < 4; ++i)
      text += "    - {face: " + std::to_string(i) +
              ", backend: recording, path: recording, camera: " + std::to_string(i == 3 ? last_camera : i) +
              "}\n";
    text += "exhibit:\n" + exhibit;
    text += "display:\n  layout: cross\n  output_size: [144, 144]\n";
    writeText(*dir_ / name, text);
    return *dir_ / name;
  }
  static std::string goodExhibit() {
    return "  relic: relic.glb\n  panorama: hall.exr\n  camera_exposure: " + std::to_string(exposure_) +
           "\n  background_frames: " + std::to_string(kBackgroundFrames) + "\n";
  }

  static fs::path* dir_;
  static float exposure_;
};

fs::path* RunConfig::dir_ = nullptr;
float RunConfig::exposure_ = 1.0f;

TEST_F(RunConfig, RunsOnTheRecordedCamerasUntilTheRecordingEnds) {
  const fs::path config = writeConfig("good.yaml", goodExhibit());
  const fs::path out = *dir_ / "out_good";
  const fs::path log = *dir_ / "good.log";
  // More frames asked for than recorded: the run ends with the recording.
  const int rc = runHolopyramid("run --headless --frames 50 --view-size 48 --png-every 4 --config " +
                                    config.string() + " --out " + out.string(),
                                log);
  const std::string text = readText(log);
  ASSERT_EQ(rc, 0) << text;
  // The calibration folder was read: two camera files, the pyramid's yaw (0.25 rad).
  EXPECT_NE(text.find("camera_REC-0.yml"), std::string::npos) << text;
  EXPECT_NE(text.find("camera_REC-1.yml"), std::string::npos) << text;
  EXPECT_NE(text.find("panorama yaw 14.32 degrees"), std::string::npos) << text;
  EXPECT_NE(text.find("ended after " + std::to_string(kVisitorFrames) + " frames"), std::string::npos)
      << text;

  std::ifstream in(out / "timing.json");
  ASSERT_TRUE(in.good()) << text;
  const nlohmann::json timing = nlohmann::json::parse(in);
  // The background frames taught the background and were not rendered.
  ASSERT_EQ(timing["frames"].get<int>(), kVisitorFrames);
  EXPECT_EQ(timing["non_finite_pixels"].get<long long>(), 0);
  int with_points = 0;
  for (const auto& frame : timing["per_frame"]) {
    EXPECT_EQ(frame["cameras_live"].get<int>(), 4);
    with_points += frame["foreground_points"].get<long long>() > 0 ? 1 : 0;
  }
  EXPECT_GE(with_points, kVisitorFrames / 2) << "the visitors of the recording were not found";
  EXPECT_TRUE(fs::exists(out / "frame_00000.png"));
  EXPECT_GT(fs::file_size(out / "quadview.mp4"), 0u);
}

// The next frame's foreground computed during this frame's rendering (the default) or after it
// (--no-overlap): the same pictures, byte for byte.
TEST_F(RunConfig, OverlappedStagesGiveTheSameFramesAsSequentialOnes) {
  const fs::path config = writeConfig("same.yaml", goodExhibit());
  for (const std::string mode : {"overlap", "sequential"}) {
    const fs::path log = *dir_ / (mode + ".log");
    const int rc = runHolopyramid("run --headless --frames 50 --view-size 48 --png-every 1 --config " +
                                      config.string() + " --out " + (*dir_ / ("out_" + mode)).string() +
                                      (mode == "sequential" ? " --no-overlap" : ""),
                                  log);
    ASSERT_EQ(rc, 0) << readText(log);
  }
  for (int frame = 0; frame < kVisitorFrames; ++frame) {
    const std::string name =
        "frame_" + std::string(frame < 10 ? "0000" : "000") + std::to_string(frame) + ".png";
    const std::string overlapped = readText(*dir_ / "out_overlap" / name);
    ASSERT_FALSE(overlapped.empty()) << name;
    EXPECT_EQ(overlapped, readText(*dir_ / "out_sequential" / name)) << name << " differs";
  }
}

// Each bad configuration exits non-zero and names the file and the field.
TEST_F(RunConfig, BadConfigurationsNameTheFileAndTheField) {
  struct Case {
    std::string name, exhibit;
    int last_camera;
    std::string field;
  };
  const std::vector<Case> cases = {
      {"no_panorama.yaml", "  relic: relic.glb\n  panorama: missing.hdr\n", 3, "exhibit.panorama"},
      {"no_relic.yaml", "  relic: nothing.glb\n  panorama: hall.exr\n", 3, "exhibit.relic"},
      {"typo.yaml", "  relic: relic.glb\n  panorama: hall.exr\n  backgroud_frames: 3\n", 3,
       "backgroud_frames"},
      {"negative.yaml", "  relic: relic.glb\n  panorama: hall.exr\n  camera_exposure: -1\n", 3,
       "exhibit.camera_exposure"},
      {"bad_camera.yaml", goodExhibit(), 9, "a camera of the recording"},
      {"no_exhibit.yaml", "", 3, "exhibit"},
  };
  for (const Case& c : cases) {
    std::string exhibit = c.exhibit;
    fs::path config;
    if (c.name == "no_exhibit.yaml") {
      writeText(*dir_ / c.name,
                "capture:\n  cameras:\n    - {face: 0, backend: recording, path: recording}\n");
      config = *dir_ / c.name;
    } else {
      config = writeConfig(c.name, exhibit, c.last_camera);
    }
    const fs::path log = *dir_ / (c.name + ".log");
    const int rc = runHolopyramid("run --headless --frames 2 --view-size 32 --png-every 0 --config " +
                                      config.string() + " --out " + (*dir_ / "out_bad").string(),
                                  log);
    const std::string text = readText(log);
    EXPECT_NE(rc, 0) << c.name << ": " << text;
    EXPECT_NE(text.find(c.field), std::string::npos) << c.name << ": " << text;
    EXPECT_EQ(text.find("terminate"), std::string::npos) << c.name << ": " << text;
  }
}

// The kiosk runs the same installation: its configuration's cameras, relic and panorama. When the
// configuration later breaks, it falls back to the last good copy, whose relative paths still
// name the files next to the configuration.
TEST_F(RunConfig, KioskRunsOnTheConfiguredCamerasAndFallsBackToTheLastGoodCopy) {
  const fs::path config = writeConfig("kiosk.yaml", goodExhibit());
  const fs::path state = *dir_ / "kiosk_state";
  const std::string arguments =
      "kiosk --headless --frames 6 --view-size 32 --health-port -1 --health-file '' "
      "--state-dir " +
      state.string() + " --config " + config.string();
  const fs::path good_log = *dir_ / "kiosk_good.log";
  int rc = runHolopyramid(arguments, good_log);
  std::string text = readText(good_log);
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find("camera_REC-0.yml"), std::string::npos)
      << "the configured cameras were not used: " << text;
  EXPECT_EQ(text.find("last good"), std::string::npos) << text;
  ASSERT_TRUE(fs::exists(state / "last-good.yaml"));

  writeConfig("kiosk.yaml", "  relic: relic.glb\n  panorama: missing.hdr\n");
  const fs::path broken_log = *dir_ / "kiosk_broken.log";
  rc = runHolopyramid(arguments, broken_log);
  text = readText(broken_log);
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find("exhibit.panorama"), std::string::npos) << "the broken field is not named: " << text;
  EXPECT_NE(text.find("last good configuration"), std::string::npos) << text;
  EXPECT_NE(text.find("camera_REC-0.yml"), std::string::npos)
      << "the last good copy did not run on the configured cameras: " << text;
  EXPECT_EQ(text.find("factory default"), std::string::npos) << text;
}

}  // namespace
