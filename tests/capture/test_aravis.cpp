// Streams from Aravis's fake GigE Vision cameras, each with an address of its own inside a
// network namespace this test creates. Skips (with the reason) where namespaces are not allowed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "fake_gv_camera.hpp"
#include "holo/capture/aravis_source.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/core/error.hpp"

using namespace holo;
using namespace holo::capture;
using namespace std::chrono_literals;

namespace {

template <class Pred>
bool waitFor(Pred pred, std::chrono::milliseconds limit) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return pred();
}

AravisCameraConfig colourCamera(const std::string& serial, const std::string& format) {
  AravisCameraConfig c;
  c.name = "aravis:" + serial;
  c.colour.serial = serial;
  c.colour.pixel_format = format;
  c.colour.width = 320;  // small frames: 77 kB, well inside a default socket buffer
  c.colour.height = 240;
  c.colour.frame_rate = 25;
  return c;
}

CaptureOptions fastRecovery(int id) {
  CaptureOptions o;
  o.camera_id = id;
  o.grab_timeout = 200ms;
  o.silence_timeout = 800ms;
  o.initial_backoff = 100ms;
  o.max_backoff = 400ms;
  return o;
}

class FakeAravis : public ::testing::Test {
 protected:
  static constexpr int kCameras = 4;

  void SetUp() override {
    if (test::findProgram("arv-fake-gv-camera-0.8").empty())
      GTEST_SKIP() << "arv-fake-gv-camera-0.8 not found (Debian package aravis-tools)";
    netns_ = std::make_unique<test::NetworkNamespace>("holo-cap-" + std::to_string(::getpid()));
    std::vector<std::string> addresses;
    for (int i = 0; i < kCameras; ++i) addresses.push_back(address(i));
    if (const std::string why = netns_->create(addresses); !why.empty())
      GTEST_SKIP() << "fake GigE cameras need a network namespace of their own: " << why;
    ASSERT_TRUE(netns_->enter()) << "setns into " << netns_->name() << " failed";
  }
  void TearDown() override {
    threads_.clear();  // stop capture before the cameras go
    cameras_.clear();
    netns_.reset();
  }

  static std::string address(int i) { return "127.0.1." + std::to_string(i + 1); }
  static std::string serial(int i) { return "HOLO-FAKE-" + std::to_string(i); }

  test::FakeCamera& startCamera(int i, int loss_per_thousand = 0) {
    cameras_.resize(std::max<std::size_t>(cameras_.size(), static_cast<std::size_t>(i + 1)));
    auto& cam = cameras_[static_cast<std::size_t>(i)];
    cam = std::make_unique<test::FakeCamera>(netns_->name(), address(i), serial(i), loss_per_thousand);
    EXPECT_TRUE(cam->start());
    return *cam;
  }
  CaptureThread& startCapture(int i, AravisCameraConfig config) {
    mailboxes_[i] = std::make_unique<LatestFrameMailbox>();
    threads_.push_back(std::make_unique<CaptureThread>(std::make_unique<AravisSource>(std::move(config)),
                                                       *mailboxes_[i], fastRecovery(i)));
    return *threads_.back();
  }

  std::unique_ptr<test::NetworkNamespace> netns_;
  std::vector<std::unique_ptr<test::FakeCamera>> cameras_;
  std::unique_ptr<LatestFrameMailbox> mailboxes_[kCameras];
  std::vector<std::unique_ptr<CaptureThread>> threads_;
};

}  // namespace

TEST_F(FakeAravis, ListsTheFakeCamerasBySerial) {
  for (int i = 0; i < kCameras; ++i) startCamera(i);
  std::vector<AravisDeviceInfo> devices;
  ASSERT_TRUE(waitFor(
      [&] {
        devices = listAravisDevices();
        return devices.size() == kCameras;
      },
      5000ms));
  for (int i = 0; i < kCameras; ++i) {
    const auto it =
        std::find_if(devices.begin(), devices.end(), [&](const auto& d) { return d.serial == serial(i); });
    ASSERT_NE(it, devices.end()) << serial(i);
    EXPECT_EQ(it->address, address(i));
    EXPECT_EQ(it->protocol, "GigEVision");
  }
  const AravisDeviceDetails details = describeAravisDevice(serial(1), true);
  EXPECT_NE(std::find(details.pixel_formats.begin(), details.pixel_formats.end(), "BayerRG8"),
            details.pixel_formats.end());
  EXPECT_TRUE(std::any_of(details.features.begin(), details.features.end(),
                          [](const std::string& f) { return f.rfind("Width = ", 0) == 0; }));
}

TEST_F(FakeAravis, FourCamerasStreamIntoFourCaptureThreads) {
  const char* formats[kCameras] = {"Mono8", "BayerRG8", "RGB8", "Mono16"};
  for (int i = 0; i < kCameras; ++i) startCamera(i);
  for (int i = 0; i < kCameras; ++i) startCapture(i, colourCamera(serial(i), formats[i]));
  ASSERT_TRUE(waitFor(
      [&] {
        for (auto& t : threads_)
          if (t->health().frames_completed < 10) return false;
        return true;
      },
      8000ms))
      << "frames: " << threads_[0]->health().frames_completed << " " << threads_[1]->health().frames_completed
      << " " << threads_[2]->health().frames_completed << " " << threads_[3]->health().frames_completed;
  for (int i = 0; i < kCameras; ++i) {
    const auto frame = mailboxes_[i]->take();
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->camera_id, i);
    EXPECT_EQ(frame->colour.type(), CV_8UC3);
    EXPECT_EQ(frame->colour.cols, 320);
    EXPECT_EQ(frame->colour.rows, 240);
    EXPECT_GT(frame->device_time.count(), 0);
    // The fake camera draws a moving gradient: a real image is not flat.
    cv::Scalar mean, stddev;
    cv::meanStdDev(frame->colour, mean, stddev);
    EXPECT_GT(stddev[0], 1.0) << formats[i];
    const CameraHealth h = threads_[static_cast<std::size_t>(i)]->health();
    EXPECT_TRUE(h.connected);
    EXPECT_EQ(h.disconnects, 0);
    EXPECT_LT(h.last_frame_age_s, 1.0);
  }
  // Device timestamps move forward.
  const auto a = mailboxes_[0]->waitAndTake(1s);
  const auto b = mailboxes_[0]->waitAndTake(1s);
  ASSERT_TRUE(a && b);
  EXPECT_GT(b->device_time, a->device_time);
  EXPECT_GT(b->sequence, a->sequence);
}

TEST_F(FakeAravis, ColourPlusDepthFromTwoDevices) {
  startCamera(0);
  startCamera(1);
  AravisCameraConfig config = colourCamera(serial(0), "BayerGB8");
  config.depth = config.colour;
  config.depth.serial = serial(1);
  config.depth.pixel_format = "Mono16";
  config.depth.depth_scale = 0.001;
  // Two free-running fake devices at 25 Hz: their frames arrive up to 20 ms apart (half a period).
  config.pair_tolerance = 20ms;
  CaptureThread& t = startCapture(0, config);
  ASSERT_TRUE(waitFor([&] { return t.health().frames_completed >= 5; }, 8000ms));
  std::optional<RgbdFrame> f;
  ASSERT_TRUE(waitFor([&] { return (f = mailboxes_[0]->take()) && !f->depth.empty(); }, 3000ms));
  EXPECT_EQ(f->depth.type(), CV_32FC1);
  EXPECT_EQ(f->depth.size(), f->colour.size());
  double hi = 0;
  cv::minMaxLoc(f->depth, nullptr, &hi);
  EXPECT_GT(hi, 0.0);
  EXPECT_LE(hi, 65.535 + 1e-3);  // uint16 / 1000
  // Paired by arrival time: the pair's skew is within the tolerance, and it is reported.
  const CameraHealth h = t.health();
  EXPECT_LE(std::abs(h.pair_skew_ms), 20.0);
  EXPECT_GE(h.frames_unpaired, 0);
  std::cout << "two devices: pair skew " << h.pair_skew_ms << " ms, " << h.frames_unpaired
            << " frames unpaired of " << h.frames_completed << "\n";
}

TEST_F(FakeAravis, FivePercentPacketLossKeepsFramesComingAndIsCounted) {
  startCamera(0, 50);
  // 160x120 Mono8 is 14 packets: about half the frames lose none of them at 5% loss.
  AravisCameraConfig config = colourCamera(serial(0), "Mono8");
  config.colour.width = 160;
  config.colour.height = 120;
  CaptureThread& t = startCapture(0, config);
  ASSERT_TRUE(waitFor(
      [&] {
        const CameraHealth h = t.health();
        return h.frames_completed >= 15 && h.frames_incomplete > 0;
      },
      8000ms))
      << "completed " << t.health().frames_completed << ", incomplete " << t.health().frames_incomplete
      << ", resends " << t.health().resends;
  const CameraHealth h = t.health();
  std::cout << "5% loss: completed " << h.frames_completed << ", incomplete " << h.frames_incomplete
            << ", resends " << h.resends << ", timed out " << h.frames_timed_out << "\n";
  EXPECT_TRUE(h.connected);
  EXPECT_EQ(h.disconnects, 0);
  // Only complete buffers became frames: the newest one has every pixel of the region.
  const auto f = mailboxes_[0]->take();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->colour.size(), cv::Size(160, 120));
}

TEST_F(FakeAravis, KilledCameraIsMarkedDisconnectedOthersContinueAndItResumes) {
  for (int i = 0; i < kCameras; ++i) startCamera(i);
  for (int i = 0; i < kCameras; ++i) startCapture(i, colourCamera(serial(i), "Mono8"));
  auto all = [&](std::int64_t n) {
    for (auto& t : threads_)
      if (t->health().frames_completed < n) return false;
    return true;
  };
  ASSERT_TRUE(waitFor([&] { return all(5); }, 8000ms));

  cameras_[2]->kill();
  CaptureThread& victim = *threads_[2];
  ASSERT_TRUE(waitFor([&] { return victim.health().disconnects >= 1; }, 5000ms));
  EXPECT_FALSE(victim.health().connected);
  // The other three keep streaming while camera 2 is gone.
  std::int64_t before[kCameras];
  for (int i = 0; i < kCameras; ++i)
    before[i] = threads_[static_cast<std::size_t>(i)]->health().frames_completed;
  std::this_thread::sleep_for(600ms);
  for (int i : {0, 1, 3})
    EXPECT_GT(threads_[static_cast<std::size_t>(i)]->health().frames_completed, before[i] + 5);
  EXPECT_GT(victim.health().last_frame_age_s, 0.5);

  startCamera(2);
  const std::int64_t victim_before = victim.health().frames_completed;
  ASSERT_TRUE(waitFor([&] { return victim.health().frames_completed >= victim_before + 5; }, 10000ms))
      << "camera 2 did not resume";
  EXPECT_TRUE(victim.health().connected);
  EXPECT_GE(victim.health().reconnects, 1);
  for (int i : {0, 1, 3}) EXPECT_EQ(threads_[static_cast<std::size_t>(i)]->health().disconnects, 0);
}

TEST_F(FakeAravis, DevicesCommandListsTheFakeCamerasWithSerialsFormatsAndCalibration) {
  for (int i = 0; i < 2; ++i) startCamera(i);
  const auto dir = std::filesystem::temp_directory_path() / ("holo-devices-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "calib");
  std::ofstream(dir / "calib" / ("camera_" + serial(1) + ".yml")) << "%YAML:1.0\n";
  const std::string log = (dir / "out.txt").string();
  // The program runs inside the namespace too, as a separate process; a fresh camera may need a
  // moment to answer discovery, so try a few times.
  std::string out;
  for (int attempt = 0; attempt < 5; ++attempt) {
    std::filesystem::remove(log);
    const int rc = test::runWithTimeout({"ip", "netns", "exec", netns_->name(), HOLO_CLI, "devices", "-v",
                                         "--calib-dir", (dir / "calib").string(), "--dev-dir", dir.string()},
                                        log, 20s);
    ASSERT_EQ(rc, 0) << "holopyramid devices failed or hung";
    std::ifstream in(log);
    out.assign(std::istreambuf_iterator<char>(in), {});
    if (out.find(serial(0)) != std::string::npos && out.find(serial(1)) != std::string::npos) break;
  }
  std::vector<std::string> lines;
  std::istringstream stream(out);
  for (std::string line; std::getline(stream, line);)
    if (line.rfind("aravis\t", 0) == 0) lines.push_back(line);
  ASSERT_EQ(lines.size(), 2u) << out;
  for (int i = 0; i < 2; ++i) {
    const auto line = std::find_if(lines.begin(), lines.end(), [&](const std::string& l) {
      return l.find("serial " + serial(i)) != std::string::npos;
    });
    ASSERT_NE(line, lines.end()) << out;
    EXPECT_NE(line->find(address(i)), std::string::npos) << *line;
    EXPECT_NE(line->find("BayerRG8"), std::string::npos) << *line;
    EXPECT_NE(line->find(i == 1 ? "calibration yes" : "calibration no"), std::string::npos) << *line;
  }
  EXPECT_NE(out.find("    Width = "), std::string::npos) << "-v lists features:\n" << out;
  std::filesystem::remove_all(dir);
}

TEST_F(FakeAravis, GenicamFeaturesAreSetByNameAndUnknownOnesAreNamed) {
  startCamera(0);
  AravisCameraConfig config = colourCamera(serial(0), "Mono8");
  config.colour.width = 0;  // the region comes from the features instead
  config.colour.height = 0;
  config.colour.features = {{"Width", "200"}, {"Height", "100"}, {"ExposureTimeAbs", "20000"}};
  startCapture(0, config);
  std::optional<RgbdFrame> f;
  ASSERT_TRUE(waitFor([&] { return (f = mailboxes_[0]->take()).has_value(); }, 8000ms));
  EXPECT_EQ(f->colour.size(), cv::Size(200, 100));
  threads_.clear();  // release the camera before opening it again below

  AravisCameraConfig wrong = colourCamera(serial(0), "Mono8");
  wrong.colour.features = {{"NoSuchFeature", "1"}};
  AravisSource source(wrong);
  try {
    ASSERT_TRUE(waitFor(
        [&] {
          try {
            source.open();
            return true;
          } catch (const InputError&) {
            throw;
          } catch (const Error&) {
            return false;  // not discovered yet
          }
        },
        5000ms));
    FAIL() << "an unknown feature was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("features.NoSuchFeature"), std::string::npos) << e.what();
  }
}
