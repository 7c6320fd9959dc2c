// The live product on its own: this program links the product's libraries only (pipeline and
// what it links; no simulation, reference renderer or evaluation: tests/architecture holds that
// for holo_pipeline). Four recorded depth cameras made here without the simulated museum (a wall,
// then a red visitor in front of it), a built-in relic and a panorama file, loaded from a
// configuration as an installation loads them, and run frame by frame through the frame loop.
// The relic must show, every pixel be finite, and the visitor reach the relic's reflections: the
// same frames without the visitor give another picture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/capture/recorder.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/config.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;

constexpr int kCameras = 4;
constexpr int kBackgroundFrames = 4;
constexpr int kVisitorFrames = 4;
constexpr int kWidth = 96, kHeight = 64;

// Camera f on the base's side f (+Z, +X, -Z, -X), 0.35 m from the axis, looking outward
// (OpenCV axes: +Z forward, +Y down).
holo::CameraModel baseCamera(int f) {
  const float azimuth = static_cast<float>(f) * 1.5707964f;
  const holo::vec3 forward(std::sin(azimuth), 0.0f, std::cos(azimuth));
  const holo::vec3 down(0.0f, -1.0f, 0.0f);
  const holo::vec3 right = glm::cross(down, forward);
  holo::mat4 pose(1.0f);
  pose[0] = holo::vec4(right, 0.0f);
  pose[1] = holo::vec4(down, 0.0f);
  pose[2] = holo::vec4(forward, 0.0f);
  pose[3] = holo::vec4(0.35f * forward + holo::vec3(0.0f, -0.1f, 0.0f), 1.0f);
  return holo::CameraModel(holo::Intrinsics::fromFov(kWidth, kHeight, 1.92f, 1.22f), pose);
}

// A grey textured wall 2.5 m away; with a visitor, a red figure 0.9 m from camera 0 fills the
// middle of its image.
holo::RgbdFrame cameraFrame(int camera, int index, bool visitor) {
  holo::RgbdFrame frame;
  frame.colour = cv::Mat(kHeight, kWidth, CV_8UC3);
  frame.depth = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(2.5f));
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const auto grey = static_cast<unsigned char>(110 + 20 * (((x / 8) + (y / 8)) % 2));
      frame.colour.at<cv::Vec3b>(y, x) = cv::Vec3b(grey, grey, grey);
    }
  if (visitor && camera == 0) {
    const cv::Rect figure(kWidth / 2 - 14, 4, 28, kHeight - 8);
    frame.colour(figure).setTo(cv::Scalar(30, 30, 210));
    frame.depth(figure).setTo(cv::Scalar(0.9f));
  }
  frame.camera_id = camera;
  frame.sequence = static_cast<std::uint64_t>(index);
  frame.device_time = holo::Nanoseconds(static_cast<std::int64_t>(index * 1e9 / 30.0));
  return frame;
}

// The installation's folder: a recording (the empty hall, then `visitor` frames), a panorama (a
// bright sky over a dark floor) and the configuration naming them and the built-in vase.
fs::path writeInstallation(const std::string& name, bool visitor) {
  const fs::path dir = holo::test::scratchDir(name + "_" + std::to_string(getpid()));
  std::vector<holo::capture::RecorderCamera> cameras;
  for (int i = 0; i < kCameras; ++i)
    cameras.push_back({"cam" + std::to_string(i), "REC-" + std::to_string(i), baseCamera(i)});
  {
    holo::capture::Recorder recorder(dir / "recording", cameras);
    for (int k = 0; k < kBackgroundFrames + kVisitorFrames; ++k)
      for (int i = 0; i < kCameras; ++i) recorder.write(cameraFrame(i, k, visitor && k >= kBackgroundFrames));
    recorder.finish();
  }
  cv::Mat panorama(64, 128, CV_32FC3);
  for (int y = 0; y < panorama.rows; ++y)
    panorama.row(y).setTo(y < panorama.rows / 2 ? cv::Scalar(1.2, 1.0, 0.8) : cv::Scalar(0.1, 0.1, 0.1));
  holo::saveHdr(dir / "hall.exr", panorama);
  fs::create_directories(dir / "calibration");
  std::string text = "capture:\n  calibration_dir: calibration\n  cameras:\n";
  for (int i = 0; i < kCameras; ++i)
    text += "    - {face: " + std::to_string(i) +
            ", backend: recording, path: recording, camera: " + std::to_string(i) + "}\n";
  text += "exhibit:\n  relic: vase\n  panorama: hall.exr\n  background_frames: " +
          std::to_string(kBackgroundFrames) + "\n";
  std::ofstream(dir / "installation.yaml") << text;
  return dir / "installation.yaml";
}

struct LoopRun {
  std::vector<holo::pipeline::FrameReport> reports;
  cv::Mat face0_hdr;  // the last frame's face view 0, linear
};

LoopRun runInstallation(const fs::path& config) {
  holo::pipeline::FrameLoopOptions options;
  options.view_size = 48;
  options.track_eyes = false;
  holo::pipeline::Installation installation =
      holo::pipeline::loadInstallation(holo::ConfigNode::loadFile(config));
  holo::pipeline::FrameLoop loop(options, std::move(installation), nullptr);
  LoopRun run;
  for (int k = 0; k < kBackgroundFrames + kVisitorFrames + 2; ++k) {
    holo::pipeline::FrameReport report = loop.step();
    if (report.cameras_ended) break;
    run.reports.push_back(report);
    run.face0_hdr = loop.lastResult().views.at(0).hdr.clone();
  }
  loop.finish();
  return run;
}

TEST(ProductFrame, TheLiveLoopRendersRecordedCamerasWithoutTheSimulation) {
  const LoopRun with = runInstallation(writeInstallation("product_frame_visitor", true));
  const LoopRun without = runInstallation(writeInstallation("product_frame_empty", false));
  ASSERT_EQ(with.reports.size(), static_cast<std::size_t>(kVisitorFrames));
  ASSERT_EQ(without.reports.size(), with.reports.size());

  std::size_t points_with = 0, points_without = 0;
  for (std::size_t k = 0; k < with.reports.size(); ++k) {
    EXPECT_EQ(with.reports[k].cameras_live, kCameras);
    EXPECT_GT(with.reports[k].relic_pixels, 0u) << "frame " << k << " shows no relic";
    EXPECT_EQ(with.reports[k].non_finite_pixels, 0);
    EXPECT_EQ(without.reports[k].non_finite_pixels, 0);
    points_with += with.reports[k].foreground_points;
    points_without += without.reports[k].foreground_points;
  }
  EXPECT_GT(points_with, 100u) << "the recorded visitor was not found";
  EXPECT_EQ(points_without, 0u) << "the empty hall has foreground";

  // Face 0 looks at the relic from camera 0's side, where the visitor stands: its reflection changes
  // the relic's pixels.
  ASSERT_FALSE(with.face0_hdr.empty());
  ASSERT_EQ(with.face0_hdr.size(), without.face0_hdr.size());
  cv::Mat difference;
  cv::absdiff(with.face0_hdr, without.face0_hdr, difference);
  cv::Mat changed;
  cv::compare(difference.reshape(1), 1e-3, changed, cv::CMP_GT);
  EXPECT_GT(cv::countNonZero(changed), 10) << "the visitor does not reach the relic's reflections";
}

}  // namespace
