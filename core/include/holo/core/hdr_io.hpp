// HDR panorama files in and out. Radiance .hdr (RGBE) is read with OpenCV; OpenEXR (any
// compression, DWAB included) with the OpenEXR library itself. Pixels come back as linear
// CV_32FC3 BGR; NaN, Inf and negative values are repaired (see sanitizeRadiance) and counted.
//
// Size limit: at most kMaxPanoramaPixels (8192x4096, 384 MiB as CV_32FC3), read from the file's
// header before any pixel is allocated; a larger panorama (16384x8192) is an InputError that
// asks for a downsampled copy.
#pragma once

#include <cstddef>
#include <filesystem>

#include "holo/core/image.hpp"

namespace holo {

inline constexpr std::size_t kMaxPanoramaPixels = std::size_t{8192} * 4096;

struct HdrImage {
  cv::Mat pixels;  // CV_32FC3, BGR, linear
  RepairCounts repaired;
};

// Throws InputError naming the file when it is missing, unreadable, not a 3-channel image or
// larger than kMaxPanoramaPixels.
HdrImage loadHdr(const std::filesystem::path& path);

// Writes a 32-bit float EXR (ZIP compression, no precision lost) or, by extension, a .hdr.
// The write goes to a temporary file that is then renamed, so a crash never leaves half a file.
void saveHdr(const std::filesystem::path& path, const cv::Mat& bgr32f);

struct LuminanceStats {
  float min = 0, max = 0, mean = 0;
};
LuminanceStats luminanceStats(const cv::Mat& bgr32f);

}  // namespace holo
