// The capture commands of the holopyramid program, run as a user would run them.
#include <gtest/gtest.h>

#include <fstream>

#include "fake_gv_camera.hpp"
#include "holo/capture/recorder.hpp"
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
      f.color = cv::Mat(24, 32, CV_8UC3, cv::Scalar(10, 20, 30));
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
