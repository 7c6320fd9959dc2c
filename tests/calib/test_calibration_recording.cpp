// The whole flow on files, as issue 19 asks: `holopyramid simulate --calibration` records the
// simulated museum with a calibration session (hand-held board before each camera, the easel at
// each marked spot, the empty hall), `calibrate --auto --config installation.yaml` calibrates the
// recording's cameras through the capture-backed rig, and `run --config` runs on the recording
// with the result. The recording's own camera models are the truth. Refusals (a camera missing,
// a board never seen, a reprojection error above the threshold) leave the previous calibration.
//
// Small for CI: 2 visitor frames, 3 background frames, a 512-pixel panorama (the cameras keep
// their 640x360: a lower resolution shrinks ChArUco's refinement gap below 4 px, docs/calib.md).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "holo/calib/calibration_io.hpp"
#include "holo/calib/pose.hpp"
#include "holo/capture/recording.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

struct CommandRun {
  int exit_code = -1;
  std::string output;
};

CommandRun holopyramid(const fs::path& dir, const std::string& args) {
  const fs::path log_path = dir / "command.log";
  const std::string command =
      std::string(HOLO_HOLOPYRAMID) + " " + args + " > " + log_path.string() + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log_path);
  std::stringstream text;
  text << in.rdbuf();
  std::cout << "$ holopyramid " << args << "\n" << text.str();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CalibrationRecording, RecordCalibrateRunAndRefusals) {
  const fs::path dir = holo::test::scratchDir("calib_recording");
  const fs::path rec = dir / "rec", config = rec / "installation.yaml", calibration = rec / "calibration";
  ASSERT_EQ(holopyramid(dir,
                        "simulate --scene museum --frames 2 --calibration --background-frames 3 "
                        "--panorama-width 512 -q --out " +
                            rec.string())
                .exit_code,
            0);
  ASSERT_TRUE(fs::exists(config));

  const CommandRun calibrated =
      holopyramid(dir, "calibrate --auto --quiet --background-frames 3 --config " + config.string());
  ASSERT_EQ(calibrated.exit_code, 0);
  const capture::Recording recording = capture::readRecording(rec);
  ASSERT_EQ(recording.cameras.size(), 4u);
  for (const capture::RecordedCamera& camera : recording.cameras) {
    ASSERT_TRUE(camera.model.has_value());
    const CameraCalibration saved = loadCameraCalibration(cameraCalibrationPath(calibration, camera.serial));
    const Intrinsics& truth = camera.model->intrinsics();
    const cv::Matx44d got = toMatx(saved.T_world_camera), want = toMatx(camera.model->T_world_camera());
    std::cout << camera.serial << ": fx " << saved.intrinsics.fx << " (true " << truth.fx
              << "), position error " << translationError(got, want) * 1000 << " mm, rotation error "
              << rotationErrorDeg(got, want) << " deg\n";
    EXPECT_NEAR(saved.intrinsics.fx, truth.fx, 0.005 * truth.fx) << camera.serial;
    EXPECT_NEAR(saved.intrinsics.fy, truth.fy, 0.005 * truth.fy) << camera.serial;
    EXPECT_LT(translationError(got, want), 0.003) << camera.serial;
    EXPECT_LT(rotationErrorDeg(got, want), 0.3) << camera.serial;
  }
  // Every frame the intrinsics step took was judged: moving ones and repeats left out.
  EXPECT_NE(calibrated.output.find("coverage image"), std::string::npos);
  EXPECT_NE(calibrated.output.find("per view RMS"), std::string::npos);

  // The run on the recording with that calibration.
  EXPECT_EQ(holopyramid(dir, "run --config " + config.string() + " --headless --frames 3 --out " +
                                 (dir / "run").string())
                .exit_code,
            0);

  // Refusals: each leaves the calibration above as it is.
  const std::string pyramid_before = readText(pyramidCalibrationPath(calibration));
  const std::string camera_before = readText(cameraCalibrationPath(calibration, recording.cameras[0].serial));
  // A camera missing: face 3 configured as a V4L2 camera that is not plugged in.
  const fs::path missing_yaml = rec / "missing_camera.yaml";
  std::string yaml = readText(config);
  const std::string face3 = "    - {face: 3, backend: recording, path: ., camera: 3}";
  ASSERT_NE(yaml.find(face3), std::string::npos);
  yaml.replace(
      yaml.find(face3), face3.size(),
      "    - {face: 3, backend: v4l2, color: {device: /dev/video-not-plugged-in, pixel_format: YUYV, "
      "width: 640, height: 360}}");
  std::ofstream(missing_yaml) << yaml;
  const CommandRun missing = holopyramid(dir, "calibrate --auto --quiet --config " + missing_yaml.string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("face3: camera: expected a camera that opens"), std::string::npos);
  // A placement board that is never seen (another dictionary than the one on the easel).
  const CommandRun unseen = holopyramid(dir,
                                        "calibrate --auto --quiet --background-frames 3 --placement-board "
                                        "charuco:7x5:0.08:0.06:DICT_4X4_50 --config " +
                                            config.string());
  EXPECT_NE(unseen.exit_code, 0);
  EXPECT_NE(unseen.output.find("not saved"), std::string::npos);
  EXPECT_NE(unseen.output.find("spot 0"), std::string::npos);
  // A reprojection error above the threshold: the intrinsics board given with one column of
  // squares too many puts every corner at the wrong place on the board (measured 47-93 px).
  const CommandRun bad_fit = holopyramid(dir,
                                         "calibrate --auto --quiet --background-frames 3 --intrinsics-board "
                                         "charuco:8x5:0.05:0.03:DICT_5X5_100 --config " +
                                             config.string());
  EXPECT_EQ(bad_fit.exit_code, 3);
  EXPECT_NE(bad_fit.output.find("FAIL"), std::string::npos);
  EXPECT_NE(bad_fit.output.find("hint: the corners fit no camera"), std::string::npos);
  EXPECT_NE(bad_fit.output.find("stays in force"), std::string::npos);
  EXPECT_EQ(readText(pyramidCalibrationPath(calibration)), pyramid_before);
  EXPECT_EQ(readText(cameraCalibrationPath(calibration, recording.cameras[0].serial)), camera_before);
}

}  // namespace
}  // namespace holo::calib
