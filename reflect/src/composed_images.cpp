#include "composed_images.hpp"

namespace holo::reflect {
namespace {

// Whether a caller still refers to the image's buffer (this object's reference aside). Read
// atomically: another thread may be letting its reference go (cv::Mat releases by an atomic
// decrement). Once the count reads 1 nobody else can take a reference, and the acquire orders that
// thread's last reads of the pixels before the writes that follow.
bool held(const cv::Mat& image) {
  return image.u != nullptr && __atomic_load_n(&image.u->refcount, __ATOMIC_ACQUIRE) > 1;
}

}  // namespace

ComposedImages::Images ComposedImages::next(const cv::Mat& static_hdr, const cv::Mat& static_display,
                                            std::uint64_t static_version,
                                            const std::vector<std::uint32_t>& covered) {
  for (Kept& kept : kept_) {
    Images& images = kept.images;
    if (held(images.hdr) || held(images.weight) || held(images.display)) continue;
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
