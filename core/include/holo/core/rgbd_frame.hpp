// One colour + depth frame from one camera, registered (depth pixel (u,v) sees the same point as
// colour pixel (u,v)). Images use OpenCV's channel order: colour is CV_8UC3 BGR, sRGB-encoded;
// depth is CV_32FC1 camera-frame Z in metres with 0 meaning "no measurement". Frames are values:
// cv::Mat shares pixel buffers, so a producer never writes into a frame after publishing it.
#pragma once

#include <chrono>
#include <cstdint>
#include <opencv2/core.hpp>

namespace holo {

using Clock = std::chrono::steady_clock;
using Nanoseconds = std::chrono::nanoseconds;

struct RgbdFrame {
  cv::Mat colour;               // CV_8UC3, BGR, sRGB
  cv::Mat depth;                // CV_32FC1, metres, 0 = invalid
  int camera_id = -1;           // index of the camera in the configuration (0..3 = faces)
  std::uint64_t sequence = 0;   // per-camera frame counter from the source, starts at 0
  Nanoseconds device_time{0};   // timestamp from the device (or the recording), source-defined epoch
  Clock::time_point host_time;  // when the frame reached the host

  bool empty() const { return colour.empty() && depth.empty(); }
  // Throws holo::Error describing the first violated invariant (types, sizes, camera id).
  void validate() const;
};

}  // namespace holo
