// USB cameras through Video4Linux2 (webcams, RealSense-class depth cameras). A device is opened
// by its node ("/dev/video2"), by bus info ("bus:usb-0000:00:14.0-3", stable across reboots as
// long as the port stays the same) or by the USB serial number ("serial:843112071234"), streamed
// with mmap buffers, and converted with pixel_format.hpp: YUYV and MJPG colour, Z16 depth.
// Kernel buffer timestamps (CLOCK_MONOTONIC, ns) become RgbdFrame::device_time.
//
// RealSense-class cameras expose colour and depth as two nodes; a V4l2CameraConfig names both,
// and colour and depth frames are paired by their kernel timestamps within pair_tolerance (one
// clock for both nodes; a driver that stamps no monotonic time gets the dequeue time), as
// frame_pairing.hpp does for two GigE devices; the depth frame keeps its own size. Buffers the driver flags
// as erroneous (V4L2_BUF_FLAG_ERROR) are counted as incomplete and re-queued. A vanished device (ENODEV,
// POLLERR) is reported as GrabStatus::Disconnected and the CaptureThread reconnects.
//
// Errors name the device and what it offers: a missing node, a busy device, a format or size the
// device does not have ("/dev/video0: pixel_format: expected one the device offers: YUYV
// 640x480 1280x720, MJPG 1920x1080, got Z16").
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/frame_pairing.hpp"
#include "holo/capture/pixel_format.hpp"

namespace holo::capture {

struct V4l2StreamConfig {
  std::string device;          // "/dev/videoN", "bus:BUS_INFO" or "serial:SERIAL"; "" = no stream
  std::string pixel_format;    // YUYV, MJPG (colour) or Z16 (depth); "" keeps the current one
  int width = 0, height = 0;   // 0 keeps the current size
  double frame_rate = 0;       // Hz; 0 keeps the current rate
  double depth_scale = 0.001;  // depth stream: metres per raw unit (RealSense Z16: 0.001 = millimetres)
  int buffers = 4;             // mmap buffer count (the driver may grant more or fewer)
};

struct V4l2CameraConfig {
  std::string name;         // for logs and statistics; defaults to "v4l2:<colour device>"
  V4l2StreamConfig colour;  // device empty = no colour stream
  V4l2StreamConfig depth;   // device empty = no depth stream
  // Colour and depth nodes both named: frames further apart are dropped and counted
  // (frame_pairing.hpp, capture.pair_tolerance_ms).
  Nanoseconds pair_tolerance{static_cast<std::int64_t>(kDefaultPairToleranceMs * 1e6)};
};

// One capture node found under /dev.
struct V4l2DeviceInfo {
  std::string path;                  // /dev/videoN
  std::string card;                  // the driver's name for the device ("Intel(R) RealSense(TM) 435")
  std::string driver;                // uvcvideo, ...
  std::string bus_info;              // usb-0000:00:14.0-3
  std::string serial;                // USB serial from sysfs; "" when the device has none
  std::vector<std::string> formats;  // "YUYV 640x480" per format and discrete size
};

// Every node named video* in `dev_dir` that is a V4L2 capture device with streaming I/O
// (metadata nodes and output devices are left out). An empty or missing folder gives an empty list.
std::vector<V4l2DeviceInfo> listV4l2Devices(const std::filesystem::path& dev_dir = "/dev");

// Resolves "/dev/videoN", "bus:..." or "serial:..." to a node in `dev_dir`. Throws holo::Error
// naming what was looked for and what was found when nothing matches.
std::string resolveV4l2Device(const std::string& spec, const std::filesystem::path& dev_dir = "/dev");

// "YUYV" <-> V4L2_PIX_FMT_YUYV. fourccFromName throws InputError for names that are not 4 chars.
std::uint32_t fourccFromName(const std::string& name);
std::string fourccToString(std::uint32_t fourcc);

struct V4l2Stream;  // one opened, mmapped node (v4l2_source.cpp)

class V4l2Source : public CameraSource {
 public:
  // Throws InputError when neither stream is named or a pixel format is not YUYV, MJPG or Z16.
  explicit V4l2Source(V4l2CameraConfig config, std::filesystem::path dev_dir = "/dev");
  ~V4l2Source() override;

  std::string name() const override;
  std::string serial() const override;  // the colour (or depth) device spec
  void open() override;
  void start() override;
  void stop() override;
  GrabResult grab(Nanoseconds timeout) override;
  double metresPerDepthUnit() const override { return config_.depth.depth_scale; }

 private:
  V4l2CameraConfig config_;
  std::filesystem::path dev_dir_;
  std::unique_ptr<V4l2Stream> colour_;
  std::unique_ptr<V4l2Stream> depth_;
  FramePairer pairer_{config_.pair_tolerance};  // colour and depth nodes
  std::uint64_t sequence_ = 0;
};

}  // namespace holo::capture
