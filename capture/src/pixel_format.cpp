#include "holo/capture/pixel_format.hpp"

#include <array>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "holo/core/error.hpp"

namespace holo::capture {

namespace {

constexpr std::array<std::pair<PixelFormat, const char*>, 12> kNames{{
    {PixelFormat::Mono8, "Mono8"},
    {PixelFormat::Mono16, "Mono16"},
    {PixelFormat::RGB8, "RGB8"},
    {PixelFormat::BGR8, "BGR8"},
    {PixelFormat::BayerRG8, "BayerRG8"},
    {PixelFormat::BayerGR8, "BayerGR8"},
    {PixelFormat::BayerGB8, "BayerGB8"},
    {PixelFormat::BayerBG8, "BayerBG8"},
    {PixelFormat::YUYV, "YUYV"},
    {PixelFormat::MJPEG, "MJPG"},
    {PixelFormat::Z16, "Z16"},
    {PixelFormat::Coord3D_C16, "Coord3D_C16"},
}};

// A cv::Mat header over the raw bytes (no copy), after checking they are all there.
cv::Mat wrap(PixelFormat f, const RawImage& raw, int type) {
  if (raw.width <= 0 || raw.height <= 0 || raw.data == nullptr)
    throw Error(toString(f) + " buffer: empty image");
  checkFrameSize(toString(f) + " buffer", "width/height", raw.width, raw.height);
  const std::size_t row = static_cast<std::size_t>(raw.width) * static_cast<std::size_t>(bytesPerPixel(f));
  const std::size_t stride = raw.stride ? raw.stride : row;
  // OpenCV needs whole elements per row; a 16-bit format with an odd stride is a broken buffer.
  if (stride % CV_ELEM_SIZE1(type) != 0 || stride > kMaxFrameBytes)
    throw Error(toString(f) + " buffer: a stride of " + std::to_string(stride) +
                " bytes is not a whole number of " + std::to_string(CV_ELEM_SIZE1(type)) +
                "-byte samples within a frame");
  const std::size_t needed = stride * static_cast<std::size_t>(raw.height - 1) + row;
  if (stride < row || raw.size < needed)
    throw Error(toString(f) + " buffer: " + std::to_string(raw.size) + " bytes, expected at least " +
                std::to_string(needed) + " for " + std::to_string(raw.width) + "x" +
                std::to_string(raw.height));
  return cv::Mat(raw.height, raw.width, type, const_cast<void*>(raw.data), stride);
}

}  // namespace

void checkFrameSize(const std::string& who, const std::string& field, long long width, long long height) {
  if (width < 1 || height < 1 || width > kMaxFrameSide || height > kMaxFrameSide)
    throw InputError(who, field,
                     "a frame of 1 to " + std::to_string(kMaxFrameSide) + " pixels a side (4K UHD fits)",
                     std::to_string(width) + "x" + std::to_string(height));
}

int bytesPerPixel(PixelFormat f) {
  switch (f) {
    case PixelFormat::Mono16:
    case PixelFormat::YUYV:
    case PixelFormat::Z16:
    case PixelFormat::Coord3D_C16:
      return 2;
    case PixelFormat::RGB8:
    case PixelFormat::BGR8:
      return 3;
    default:
      return 1;
  }
}

PixelFormat pixelFormatFromName(const std::string& name) {
  for (const auto& [format, text] : kNames)
    if (name == text) return format;
  if (name == "MJPEG" || name == "JPEG") return PixelFormat::MJPEG;
  std::string all;
  for (const auto& [format, text] : kNames) all += (all.empty() ? "" : ", ") + std::string(text);
  throw InputError("", "pixel_format", "one of " + all, name);
}

std::string toString(PixelFormat format) {
  for (const auto& [f, text] : kNames)
    if (f == format) return text;
  return "unknown";
}

std::vector<std::string> pixelFormatNames() {
  std::vector<std::string> out;
  for (const auto& [f, text] : kNames) out.emplace_back(text);
  return out;
}

bool isDepthFormat(PixelFormat format) {
  return format == PixelFormat::Z16 || format == PixelFormat::Coord3D_C16;
}

cv::Mat convertToColour(PixelFormat format, const RawImage& raw) {
  cv::Mat out;
  switch (format) {
    case PixelFormat::Mono8:
      cv::cvtColor(wrap(format, raw, CV_8UC1), out, cv::COLOR_GRAY2BGR);
      break;
    case PixelFormat::Mono16: {
      cv::Mat eight;
      wrap(format, raw, CV_16UC1).convertTo(eight, CV_8U, 1.0 / 256.0);
      cv::cvtColor(eight, out, cv::COLOR_GRAY2BGR);
      break;
    }
    case PixelFormat::RGB8:
      cv::cvtColor(wrap(format, raw, CV_8UC3), out, cv::COLOR_RGB2BGR);
      break;
    case PixelFormat::BGR8:
      wrap(format, raw, CV_8UC3).copyTo(out);
      break;
    // PFNC names the first row, OpenCV the second: RG <-> BG, GR <-> GB.
    case PixelFormat::BayerRG8:
      cv::cvtColor(wrap(format, raw, CV_8UC1), out, cv::COLOR_BayerBG2BGR);
      break;
    case PixelFormat::BayerBG8:
      cv::cvtColor(wrap(format, raw, CV_8UC1), out, cv::COLOR_BayerRG2BGR);
      break;
    case PixelFormat::BayerGR8:
      cv::cvtColor(wrap(format, raw, CV_8UC1), out, cv::COLOR_BayerGB2BGR);
      break;
    case PixelFormat::BayerGB8:
      cv::cvtColor(wrap(format, raw, CV_8UC1), out, cv::COLOR_BayerGR2BGR);
      break;
    case PixelFormat::YUYV:
      cv::cvtColor(wrap(format, raw, CV_8UC2), out, cv::COLOR_YUV2BGR_YUYV);
      break;
    case PixelFormat::MJPEG: {
      if (raw.data == nullptr || raw.size == 0) throw Error("MJPG buffer: empty");
      checkFrameSize("MJPG buffer", "width/height", raw.width, raw.height);
      // imdecode would also try JPEG 2000, TIFF, WebP and more on whatever the camera sent.
      if (raw.size < 3 || std::memcmp(raw.data, "\xff\xd8\xff", 3) != 0)
        throw Error("MJPG buffer: not a JPEG (no SOI marker)");
      const cv::Mat bytes(1, static_cast<int>(raw.size), CV_8UC1, const_cast<void*>(raw.data));
      out = cv::imdecode(bytes, cv::IMREAD_COLOR);
      if (out.empty())
        throw Error("MJPG buffer: not a decodable JPEG (" + std::to_string(raw.size) + " bytes)");
      if (out.cols != raw.width || out.rows != raw.height)
        throw Error("MJPG buffer: decoded " + std::to_string(out.cols) + "x" + std::to_string(out.rows) +
                    ", expected " + std::to_string(raw.width) + "x" + std::to_string(raw.height));
      break;
    }
    case PixelFormat::Z16:
    case PixelFormat::Coord3D_C16:
      throw Error(toString(format) + " is a depth format, not colour");
  }
  return out;
}

cv::Mat convertToDepth(PixelFormat format, const RawImage& raw, double metres_per_unit) {
  if (format != PixelFormat::Mono16 && format != PixelFormat::Z16 && format != PixelFormat::Coord3D_C16)
    throw Error(toString(format) + " cannot carry depth (use Mono16, Z16 or Coord3D_C16)");
  if (!(metres_per_unit > 0)) throw Error("depth scale must be positive");
  // All three are little-endian uint16, as is every host this runs on (x86-64, aarch64).
  cv::Mat out;
  wrap(format, raw, CV_16UC1).convertTo(out, CV_32FC1, metres_per_unit);
  return out;
}

}  // namespace holo::capture
