// HDR -> display: exposure, Reinhard on luminance (hue kept), sRGB encoding. For pictures
// people look at (PNG); metrics use linear radiance (image_metrics.hpp).
#pragma once

#include <opencv2/core.hpp>

namespace holo::reflect {

// Exposure that maps the log-average luminance of the non-zero pixels to 0.18 (1 when the
// image is black). Non-finite pixels are ignored.
float autoExposure(const cv::Mat& hdr_bgr32f);
// CV_32FC3 linear BGR -> CV_8UC3 sRGB BGR: L' = L e / (1 + L e) applied through the luminance.
cv::Mat toneMap(const cv::Mat& hdr_bgr32f, float exposure);

}  // namespace holo::reflect
