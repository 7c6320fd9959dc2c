// The images a view's composition hands out each frame: the static images with the foreground
// composed over them, kept and written again once no caller holds them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace holo::reflect {

// A view's composed images: `hdr` (CV_32FC3) and `display` (CV_8UC3, only where a static display
// is given) start as the static ones, `weight` (CV_32FC1) as zeros, and the caller then writes the
// covered pixels alone. A set that no caller holds any more (its buffers referenced by this object
// only) is handed out again: made from the same static images (the same `static_version`), only the
// covered pixels are restored (at 540x540 a fifth of the view); otherwise the static images are
// copied into it whole, in memory already mapped. While callers hold every kept set a fresh one is
// allocated, so an image handed out earlier never changes.
class ComposedImages {
 public:
  struct Images {
    cv::Mat hdr, weight, display;
  };
  // `covered`: the pixels (y * width + x) the caller may write in the returned images, the same
  // list for one `static_version`, which must change whenever the static images or `covered` do.
  Images next(const cv::Mat& static_hdr, const cv::Mat& static_display, std::uint64_t static_version,
              const std::vector<std::uint32_t>& covered);

 private:
  struct Kept {
    Images images;
    std::uint64_t static_version = 0;
  };
  // Two sets: the one the caller still shows while the next frame composes into the other.
  std::array<Kept, 2> kept_;
};

}  // namespace holo::reflect
