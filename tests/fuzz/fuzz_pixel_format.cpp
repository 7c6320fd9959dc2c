// Camera buffers of any size and format: an 8-byte header (format, width, height, row padding,
// depth scale) followed by the buffer, through convertToColor / convertToDepth. A camera may
// announce any size and stride; only holo::Error (a failed frame) may come out, and a converted
// image must have the announced size.
#include <cstddef>
#include <cstdint>

#include "holo/capture/pixel_format.hpp"
#include "holo/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using holo::capture::PixelFormat;
  if (size < 8) return 0;
  const auto format = static_cast<PixelFormat>(data[0] % 12);
  const int width = data[1] | (data[2] << 8);
  const int height = data[3] | (data[4] << 8);
  const std::size_t padding = data[5];
  const double metres_per_unit = data[6] / 1000.0;
  const bool packed = (data[7] & 1) != 0;
  const std::size_t row = static_cast<std::size_t>(width) * static_cast<std::size_t>(bytesPerPixel(format));
  const holo::capture::RawImage raw{data + 8, size - 8, width, height, packed ? 0 : row + padding};
  try {
    const cv::Mat out = holo::capture::isDepthFormat(format) || format == PixelFormat::Mono16
                            ? holo::capture::convertToDepth(format, raw, metres_per_unit)
                            : holo::capture::convertToColour(format, raw);
    if (out.cols != width || out.rows != height) __builtin_trap();
  } catch (const holo::Error&) {
  }
  return 0;
}
