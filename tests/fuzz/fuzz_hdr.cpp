// HDR panoramas: Radiance .hdr (OpenCV's RGBE reader) or OpenEXR (the OpenEXR library), chosen
// by the EXR magic number, then our NaN/Inf/negative repair. Only holo::InputError may come out;
// every pixel that comes back must be finite and non-negative.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_files.hpp"
#include "holo/core/error.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/log.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  holo::initLogging(holo::LogLevel::Off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const bool exr = bytes.substr(0, 4) == std::string_view("\x76\x2f\x31\x01", 4);
  const auto path = holo::fuzz::scratchDir() / (exr ? "input.exr" : "input.hdr");
  holo::fuzz::writeBytes(path, bytes);
  try {
    const holo::HdrImage image = holo::loadHdr(path);
    if (image.pixels.type() != CV_32FC3) __builtin_trap();
    for (auto it = image.pixels.begin<cv::Vec3f>(); it != image.pixels.end<cv::Vec3f>(); ++it)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite((*it)[c]) || (*it)[c] < 0) __builtin_trap();
  } catch (const holo::InputError&) {
  }
  return 0;
}
