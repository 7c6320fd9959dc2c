// The capture commands of the holopyramid program, run as a user would run them.
#include <gtest/gtest.h>

#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include "fake_gv_camera.hpp"

#include "holo/capture/recorder.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/hdr_io.hpp"
#include "shared_data.hpp"

using namespace holo;
using namespace holo::capture;
using namespace std::chrono_literals;

namespace {

// Runs holopyramid with `args`; returns its exit code and fills `out` with stdout and stderr.
int runCli(const std::vector<std::string>& args, const std::filesystem::path& log, std::string& out) {
  std::vector<std::string> argv{HOLO_CLI};
  argv.insert(argv.end(), args.begin(), args.end());
  std::filesystem::remove(log);
  const int rc = test::runWithTimeout(argv, log.string(), 60s);
  std::ifstream in(log);
  out.assign(std::istreambuf_iterator<char>(in), {});
  return rc;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(CaptureCli, InfoDescribesARecording) {
  const auto dir = test::scratchDir("cli_info_recording");
  {
    Intrinsics K = Intrinsics::fromFov(32, 24, 1.5f, 1.0f);
    Recorder rec(dir / "rec", {{"north", "SN-7", CameraModel(K, mat4(1.0f))}}, 1000.0);
    for (int i = 0; i < 5; ++i) {
      RgbdFrame f;
      f.camera_id = 0;
      f.device_time = std::chrono::milliseconds(100 * i);  // 10 Hz
      f.colour = cv::Mat(24, 32, CV_8UC3, cv::Scalar(10, 20, 30));
      f.depth = cv::Mat(24, 32, CV_32FC1, cv::Scalar(2.5f));
      f.depth(cv::Rect(0, 0, 16, 24)) = 0.0f;  // half the pixels without depth
      rec.write(f);
    }
  }
  std::string out;
  ASSERT_EQ(runCli({"info", (dir / "rec").string()}, dir / "out.txt", out), 0) << out;
  EXPECT_TRUE(contains(out, "type: recording (holopyramid)")) << out;
  EXPECT_TRUE(contains(out, "serial: SN-7")) << out;
  EXPECT_TRUE(contains(out, "frames: 5")) << out;
  EXPECT_TRUE(contains(out, "rate hz: 10")) << out;
  EXPECT_TRUE(contains(out, "valid 50%")) << out;
  EXPECT_TRUE(contains(out, "range m 2.5 - 2.5")) << out;

  // Something that is neither a panorama nor a recording: exit code 2 and the path in the error.
  std::filesystem::create_directories(dir / "empty");
  EXPECT_EQ(runCli({"info", (dir / "empty").string()}, dir / "out.txt", out), 2) << out;
  EXPECT_TRUE(contains(out, (dir / "empty").string())) << out;
}

TEST(CaptureCli, SimulateWritesARecordingWithTruthBackgroundsPanoramaAndContactSheet) {
  const auto dir = test::scratchDir("cli_simulate");
  // A small scene file: quick, and it shows --scene takes files too.
  std::ofstream(dir / "small.yaml")
      << "base: room\ncamera: {width: 96, height: 54, fps: 10}\nvisitors: 2\nseed: 5\n";
  const auto out_dir = dir / "out";
  std::string out;
  ASSERT_EQ(runCli({"simulate", "--scene", (dir / "small.yaml").string(), "--frames", "3", "--out",
                    out_dir.string(), "--panorama-width", "64", "--quiet"},
                   dir / "log.txt", out),
            0)
      << out;
  const Recording recording = readRecording(out_dir);
  ASSERT_EQ(recording.cameras.size(), 4u);
  for (const auto& camera : recording.cameras) {
    ASSERT_EQ(camera.frames.size(), 3u);
    EXPECT_DOUBLE_EQ(camera.frames[2].timestamp_s, 0.2);  // frame 2 at 10 fps
    ASSERT_TRUE(camera.model.has_value());
    const std::string cam = "cam" + std::to_string(camera.id);
    const cv::Mat truth =
        cv::imread((out_dir / "truth" / cam / "depth" / "000002.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(truth.type(), CV_16UC1) << cam;
    EXPECT_EQ(truth.size(), cv::Size(96, 54));
    EXPECT_GT(cv::countNonZero(truth), 96 * 54 / 2) << "a room surrounds every camera";
    const cv::Mat mask =
        cv::imread((out_dir / "truth" / cam / "foreground" / "000000.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(mask.type(), CV_8UC1) << cam;
    const cv::Mat background =
        cv::imread((out_dir / "background" / cam / "depth.png").string(), cv::IMREAD_UNCHANGED);
    EXPECT_EQ(background.type(), CV_16UC1) << cam;
  }
  // The recorded (noisy) depth and the truth agree on most pixels to within the noise.
  const RgbdFrame measured = RecordingSource(recording.cameras[0]).load(0);
  const cv::Mat truth = depthFromU16(
      cv::imread((out_dir / "truth" / "cam0" / "depth" / "000000.png").string(), cv::IMREAD_UNCHANGED),
      1000.0);
  cv::Mat both = (measured.depth > 0) & (truth > 0);
  cv::Mat diff;
  cv::absdiff(measured.depth, truth, diff);
  EXPECT_GT(cv::countNonZero(both & (diff < 0.1f)), cv::countNonZero(both) * 9 / 10);

  const HdrImage panorama = loadHdr(out_dir / "panorama.exr");
  EXPECT_EQ(panorama.pixels.size(), cv::Size(64, 32));
  const cv::Mat sheet = cv::imread((out_dir / "contact_sheet.png").string());
  EXPECT_EQ(sheet.size(), cv::Size(4 * 96, 4 * 54));  // four cameras x colour, depth, truth, mask
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << "left behind";

  // The same command again: the folder exists, nothing is overwritten (exit code 2, InputError).
  EXPECT_EQ(runCli({"simulate", "--scene", "room", "--frames", "1", "--out", out_dir.string()},
                   dir / "log.txt", out),
            2);
  EXPECT_TRUE(contains(out, out_dir.string())) << out;
  EXPECT_EQ(runCli({"simulate", "--scene", "no-such-scene", "--frames", "1", "--out", (dir / "x").string()},
                   dir / "log.txt", out),
            2);
  EXPECT_FALSE(std::filesystem::exists(dir / "x"));
}
