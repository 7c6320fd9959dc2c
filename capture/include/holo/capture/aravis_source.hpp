// GigE Vision / USB3 Vision cameras through Aravis 0.8. A device is opened by serial number
// (never by enumeration order), configured through GenICam features (region, PixelFormat,
// AcquisitionFrameRate), and streamed with a pool of buffers. Only complete buffers become
// frames; incomplete ones (missing packets) are counted and re-queued. Device timestamps (ns)
// become RgbdFrame::device_time.
//
// A depth camera is a colour stream plus a depth stream: two devices (colour serial + depth
// serial); the depth buffer nearest in device time is paired with each colour buffer. Either
// stream alone is fine too (a colour-only or depth-only camera).
//
// Loss of the device (heartbeat "control-lost", or the capture thread's silence timeout) is
// reported as GrabStatus::Disconnected; the CaptureThread then stops and re-opens the source with
// back-off, and open() finds the camera again by serial wherever it reappears.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/frame_pairing.hpp"
#include "holo/capture/pixel_format.hpp"

namespace holo::capture {

struct AravisStreamConfig {
  std::string serial;          // device serial number (DeviceSerialNumber)
  std::string pixel_format;    // PFNC name; "" keeps the device's current format
  int width = 0, height = 0;   // 0 keeps the device's current region
  double frame_rate = 0;       // Hz; 0 keeps the device's current rate
  double depth_scale = 0.001;  // depth stream: metres per raw unit (0.001 = millimetres)
  int buffers = 8;             // buffer pool size
  // Further GenICam features set in this order after the format, region and rate, by name and
  // value as text ("ExposureTime" = "8000", "GainAuto" = "Off"). An unknown feature or a
  // rejected value is an InputError naming the feature.
  std::vector<std::pair<std::string, std::string>> features;
  // GigE Vision on loopback cannot use the packet socket; "auto" disables it for 127.x cameras.
  enum class PacketSocket { Auto, On, Off } packet_socket = PacketSocket::Auto;
};

struct AravisCameraConfig {
  std::string name;           // for logs and statistics; defaults to the colour serial
  AravisStreamConfig colour;  // serial empty = no colour stream
  AravisStreamConfig depth;   // serial empty = no depth stream
  // Colour and depth from two devices: frames further apart than this are not paired
  // (frame_pairing.hpp, capture.pair_tolerance_ms).
  Nanoseconds pair_tolerance{static_cast<std::int64_t>(kDefaultPairToleranceMs * 1e6)};
};

struct AravisDevice;  // one opened GenICam device and its stream (aravis_source.cpp)

class AravisSource : public CameraSource {
 public:
  explicit AravisSource(AravisCameraConfig config);
  ~AravisSource() override;

  std::string name() const override;
  std::string serial() const override;
  void open() override;
  void start() override;
  void stop() override;
  GrabResult grab(Nanoseconds timeout) override;
  double metresPerDepthUnit() const override { return config_.depth.depth_scale; }

 private:
  AravisCameraConfig config_;
  std::unique_ptr<AravisDevice> colour_;
  std::unique_ptr<AravisDevice> depth_;
  std::uint64_t sequence_ = 0;
  std::int64_t resends_before_ = 0;             // resends of earlier connections
  FramePairer pairer_{config_.pair_tolerance};  // colour and depth devices
};

// One GenICam device found on the network or USB.
struct AravisDeviceInfo {
  std::string id, vendor, model, serial, address, protocol;
};
// Discovers devices (about a second on GigE). Thread-safe: Aravis's device list is global, so
// every use of it in this module goes through one lock.
std::vector<AravisDeviceInfo> listAravisDevices();

// Opens the device briefly: its pixel formats and, when `features` is set, "Name = value" for
// every readable GenICam feature under Root. Throws holo::Error when it cannot be opened.
struct AravisDeviceDetails {
  std::vector<std::string> pixel_formats;
  std::vector<std::string> features;
};
AravisDeviceDetails describeAravisDevice(const std::string& serial, bool features);

}  // namespace holo::capture
