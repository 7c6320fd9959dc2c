// HDR panorama files in and out. Radiance .hdr (RGBE) is read with OpenCV; OpenEXR (any
// compression, DWAB included) with the OpenEXR library itself. Pixels come back as linear
// CV_32FC3 BGR; NaN, Inf and negative values are repaired (see sanitizeRadiance) and counted.
#pragma once

#include <filesystem>

#include "holo/core/image.hpp"

namespace holo {

struct HdrImage {
  cv::Mat pixels;  // CV_32FC3, BGR, linear
  RepairCounts repaired;
};

// Throws InputError naming the file when it is missing, unreadable or not a 3-channel image.
HdrImage loadHdr(const std::filesystem::path& path);

// Writes a 32-bit float EXR (ZIP compression, no precision lost) or, by extension, a .hdr.
// The write goes to a temporary file that is then renamed, so a crash never leaves half a file.
void saveHdr(const std::filesystem::path& path, const cv::Mat& bgr32f);

struct LuminanceStats {
  float min = 0, max = 0, mean = 0;
};
LuminanceStats luminanceStats(const cv::Mat& bgr32f);

}  // namespace holo
