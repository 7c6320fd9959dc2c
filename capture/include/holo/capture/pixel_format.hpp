// Raw camera buffers -> the project's images. Colour comes out CV_8UC3 BGR (sRGB as the camera
// delivered it), depth CV_32FC1 metres with 0 = invalid. Names follow GenICam PFNC for Aravis
// (Mono8, BayerRG8, Coord3D_C16...) and V4L2 FourCCs for UVC devices (YUYV, MJPG, Z16).
//
// Bayer names give the colour of the first two pixels of the first row (PFNC); OpenCV names its
// codes by the second row, so BayerRG8 is demosaiced with cv::COLOR_BayerBG2BGR (see the table in
// pixel_format.cpp; the test builds each mosaic from a known colour to pin this down).
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace holo::capture {

enum class PixelFormat {
  Mono8,
  Mono16,
  RGB8,
  BGR8,
  BayerRG8,
  BayerGR8,
  BayerGB8,
  BayerBG8,
  YUYV,        // V4L2 YUYV 4:2:2 (Y0 U Y1 V), 2 bytes per pixel
  MJPEG,       // V4L2 MJPG: one JPEG image per buffer, variable size
  Z16,         // V4L2 Z16: little-endian uint16 depth units
  Coord3D_C16  // GenICam 3D: uint16 Z in depth units
};

// Throws holo::InputError (field "pixel_format") naming the accepted names.
PixelFormat pixelFormatFromName(const std::string& name);
std::string toString(PixelFormat format);
std::vector<std::string> pixelFormatNames();
bool isDepthFormat(PixelFormat format);  // Z16, Coord3D_C16 (Mono16 can be either, by config)
// Bytes per pixel of a packed buffer; MJPEG has no fixed size and counts 1 (its buffer is at
// most width x height bytes in practice).
int bytesPerPixel(PixelFormat format);

// The largest frame a camera may announce, a side: 4096 (4K UHD fits). A converted colour frame
// is then at most 48 MiB (BGR) and a depth frame 64 MiB (float). Sources check the size a camera
// announces before they allocate buffers for it; the converters check every buffer again.
inline constexpr int kMaxFrameSide = 4096;
// The most bytes one camera buffer may hold: the largest frame at 4 bytes a pixel.
inline constexpr std::size_t kMaxFrameBytes = std::size_t{kMaxFrameSide} * kMaxFrameSide * 4;
// Throws InputError naming `who` and `field` when width or height is outside 1..kMaxFrameSide.
void checkFrameSize(const std::string& who, const std::string& field, long long width, long long height);

struct RawImage {
  const void* data = nullptr;
  std::size_t size = 0;  // bytes available
  int width = 0;
  int height = 0;
  std::size_t stride = 0;  // bytes per row; 0 = packed
};

// Throws holo::Error when the size is outside 1..kMaxFrameSide, the buffer is too small for
// width x height (or its stride is not a whole number of pixels), or it cannot be decoded (a
// truncated JPEG); the caller counts the frame as failed.
cv::Mat convertToColour(PixelFormat format, const RawImage& raw);
// Mono16, Z16 and Coord3D_C16: units * metres_per_unit; 0 stays 0 (invalid).
cv::Mat convertToDepth(PixelFormat format, const RawImage& raw, double metres_per_unit);

}  // namespace holo::capture
