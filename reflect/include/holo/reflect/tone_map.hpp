// HDR -> display: exposure, Reinhard on luminance (hue kept), sRGB encoding. For pictures
// people look at (PNG); metrics use linear radiance (image_metrics.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"

namespace holo::reflect {

// Exposure that maps the log-average luminance of the non-zero pixels to 0.18 (1 when the
// image is black). Non-finite pixels are ignored.
float autoExposure(const cv::Mat& hdr_bgr32f);
// One linear RGB radiance -> sRGB BGR bytes: L' = L e / (1 + L e) applied through the luminance;
// non-finite -> black. The sRGB curve is read from a table of 2^14 steps over [0, 1] (within 0.1
// of a code value of the exact curve), so the renderer can tone-map single pixels cheaply.
cv::Vec3b toneMapPixel(const vec3& rgb, float exposure);
// The same, unrounded: the exact sRGB curve's codes in [0, 255], RGB order; for telling whether a
// change of radiance would move a displayed code at all.
vec3 toneMapCodes(const vec3& rgb, float exposure);
// The most a change of at most `radiance` (linear, any channel or channels, either sign) can move a
// displayed sRGB code at `exposure` (> 0), whatever the pixel it is added to: the hue-keeping
// Reinhard moves a channel by at most twice the exposed change (its own and through the
// luminance), and the sRGB curve, concave, moves most from black.
float largestCodeChange(float radiance, float exposure);
// CV_32FC3 linear BGR -> CV_8UC3 sRGB BGR, toneMapPixel per pixel.
cv::Mat toneMap(const cv::Mat& hdr_bgr32f, float exposure);
// The same at the listed pixels only (y * width + x, each < hdr's pixel count), black elsewhere:
// the frame renderer's image where the relic is not is black anyway.
cv::Mat toneMapCovered(const cv::Mat& hdr_bgr32f, const std::vector<std::uint32_t>& pixels, float exposure);

}  // namespace holo::reflect
