#include "holo/eval/scoring.hpp"

#include <filesystem>

#include "holo/core/hdr_io.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/reference/image_metrics.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::eval {

cv::Mat displayedImage(const cv::Mat& hdr, float exposure) {
  cv::Mat out;
  reflect::toneMap(hdr, exposure).convertTo(out, CV_32FC3, 1.0 / 255.0);
  return out;
}

double ForegroundScoring::mse(const cv::Mat& hdr) const {
  return reference::mse(displayed(hdr), truth);
}

double ForegroundScoring::foregroundMse(const cv::Mat& hdr) const {
  return region_pixels > 0 ? reference::mse(displayed(hdr), truth, region) : 0.0;
}

ForegroundScoring foregroundScoring(const cv::Mat& truth_hdr, const cv::Mat& without_hdr, float threshold) {
  ForegroundScoring s;
  s.exposure = reflect::autoExposure(truth_hdr);
  s.truth = s.displayed(truth_hdr);
  s.region = reference::foregroundRegion(s.truth, s.displayed(without_hdr), threshold);
  s.region_pixels = cv::countNonZero(s.region);
  return s;
}

void writeImagePair(const std::string& exr_path, const cv::Mat& hdr, float exposure) {
  saveHdr(exr_path, hdr);
  const std::filesystem::path png = std::filesystem::path(exr_path).replace_extension(".png");
  display::writePngAtomically(png,
                              reflect::toneMap(hdr, exposure > 0.0f ? exposure : reflect::autoExposure(hdr)));
}

}  // namespace holo::eval
