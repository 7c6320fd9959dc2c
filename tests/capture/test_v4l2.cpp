// What can be tested of V4L2 without a camera: FourCC handling, configuration checks, and the
// errors for missing devices, non-V4L2 nodes and empty device folders. Streaming itself needs a
// real device (see docs/capture.md); the conversions it uses are tested on real byte layouts in
// test_pixel_format.cpp.
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <filesystem>
#include <fstream>

#include "holo/capture/v4l2_source.hpp"
#include "holo/core/error.hpp"

using namespace holo;
using namespace holo::capture;

namespace {

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::filesystem::path emptyDevDir() {
  const auto dir = std::filesystem::temp_directory_path() / ("holo-v4l2-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST(V4l2, FourccRoundTripsAndTrimsPadding) {
  EXPECT_EQ(fourccFromName("YUYV"), V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(fourccFromName("MJPG"), V4L2_PIX_FMT_MJPEG);
  EXPECT_EQ(fourccFromName("Z16 "), V4L2_PIX_FMT_Z16);
  EXPECT_EQ(fourccToString(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(fourccToString(V4L2_PIX_FMT_Z16), "Z16");  // the padding space is not part of the name
  EXPECT_EQ(pixelFormatFromName(fourccToString(V4L2_PIX_FMT_MJPEG)), PixelFormat::MJPEG);
  EXPECT_THROW(fourccFromName("YUV"), InputError);
}

TEST(V4l2, EmptyOrMissingDeviceFolderListsNothing) {
  const auto dir = emptyDevDir();
  EXPECT_TRUE(listV4l2Devices(dir).empty());
  EXPECT_TRUE(listV4l2Devices(dir / "does-not-exist").empty());
  // A file named like a device that is not one is skipped, not reported as a camera.
  std::ofstream(dir / "video0") << "not a device";
  EXPECT_TRUE(listV4l2Devices(dir).empty());
  std::filesystem::remove_all(dir);
}

TEST(V4l2, OpeningByBusInfoOrSerialWithNoDevicesSaysWhatWasSearched) {
  const auto dir = emptyDevDir();
  const std::string by_bus = messageOf([&] { resolveV4l2Device("bus:usb-0000:00:14.0-3", dir); });
  EXPECT_TRUE(contains(by_bus, "bus info usb-0000:00:14.0-3")) << by_bus;
  EXPECT_TRUE(contains(by_bus, "found: none")) << by_bus;
  EXPECT_TRUE(contains(by_bus, dir.string())) << by_bus;
  const std::string by_serial = messageOf([&] { resolveV4l2Device("serial:843112071234", dir); });
  EXPECT_TRUE(contains(by_serial, "serial 843112071234")) << by_serial;
  EXPECT_EQ(resolveV4l2Device("/dev/video7", dir), "/dev/video7");  // a node path is taken as is

  V4l2CameraConfig config;
  config.colour.device = "serial:843112071234";
  V4l2Source source(config, dir);
  EXPECT_THROW(source.open(), Error);
  std::filesystem::remove_all(dir);
}

TEST(V4l2, MissingNodeAndNonV4l2NodeErrorsNameTheDevice) {
  V4l2CameraConfig missing;
  missing.colour.device = "/dev/holo-test-no-such-video";
  V4l2Source a(missing);
  const std::string why = messageOf([&] { a.open(); });
  EXPECT_TRUE(contains(why, "/dev/holo-test-no-such-video")) << why;
  EXPECT_TRUE(contains(why, "no such V4L2 device")) << why;

  // /dev/null opens but answers no V4L2 ioctl.
  V4l2CameraConfig null_device;
  null_device.colour.device = "/dev/null";
  V4l2Source b(null_device);
  const std::string not_v4l2 = messageOf([&] { b.open(); });
  EXPECT_TRUE(contains(not_v4l2, "/dev/null: not a V4L2 device")) << not_v4l2;
  // A source that failed to open reports itself disconnected instead of crashing.
  EXPECT_EQ(b.grab(Nanoseconds(1000000)).status, GrabStatus::Disconnected);
}

TEST(V4l2, ConfigurationErrorsNameTheField) {
  V4l2CameraConfig none;
  none.name = "face-north";
  const std::string empty = messageOf([&] { V4l2Source s(none); });
  EXPECT_TRUE(contains(empty, "face-north")) << empty;

  V4l2CameraConfig rgb_depth;
  rgb_depth.name = "face-east";
  rgb_depth.depth.device = "/dev/video2";
  rgb_depth.depth.pixel_format = "YUYV";
  const std::string wrong = messageOf([&] { V4l2Source s(rgb_depth); });
  EXPECT_TRUE(contains(wrong, "depth.pixel_format")) << wrong;
  EXPECT_TRUE(contains(wrong, "Z16")) << wrong;

  V4l2CameraConfig bad_colour;
  bad_colour.colour.device = "/dev/video0";
  bad_colour.colour.pixel_format = "RGB3";
  EXPECT_THROW(V4l2Source s(bad_colour), InputError);

  V4l2CameraConfig bad_scale;
  bad_scale.depth.device = "/dev/video2";
  bad_scale.depth.pixel_format = "Z16";
  bad_scale.depth.depth_scale = 0;
  EXPECT_THROW(V4l2Source s(bad_scale), InputError);
}
