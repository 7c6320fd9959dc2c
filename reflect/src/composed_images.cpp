#include "composed_images.hpp"

#include "holo/core/image_sharing.hpp"

namespace holo::reflect {

ComposedImages::Images ComposedImages::next(const cv::Mat& static_hdr, const cv::Mat& static_display,
                                            std::uint64_t static_version,
                                            const std::vector<std::uint32_t>& covered) {
  for (Kept& kept : kept_) {
    Images& images = kept.images;
    if (sharedElsewhere(images.hdr) || sharedElsewhere(images.weight) || sharedElsewhere(images.display))
      continue;
    const bool same_static = !images.hdr.empty() && kept.static_version == static_version &&
                             images.hdr.size() == static_hdr.size() &&
                             images.display.empty() == static_display.empty();
    if (same_static) {
      // Everything the caller wrote since lies on the covered pixels.
      const int width = static_hdr.cols;
      for (const std::uint32_t p : covered) {
        const int x = int(p % std::uint32_t(width)), y = int(p / std::uint32_t(width));
        images.hdr.at<cv::Vec3f>(y, x) = static_hdr.at<cv::Vec3f>(y, x);
        images.weight.at<float>(y, x) = 0.0f;
        if (!static_display.empty()) images.display.at<cv::Vec3b>(y, x) = static_display.at<cv::Vec3b>(y, x);
      }
    } else {
      static_hdr.copyTo(images.hdr);
      images.weight.create(static_hdr.size(), CV_32FC1);
      images.weight.setTo(0);
      if (static_display.empty())
        images.display.release();
      else
        static_display.copyTo(images.display);
      kept.static_version = static_version;
    }
    return images;
  }
  return {static_hdr.clone(), cv::Mat::zeros(static_hdr.size(), CV_32FC1),
          static_display.empty() ? cv::Mat() : static_display.clone()};
}

}  // namespace holo::reflect
