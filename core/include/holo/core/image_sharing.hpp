// Whether an image's pixels are shared: what a producer that hands out images and writes them
// again once nobody holds them asks before writing.
#pragma once

#include <opencv2/core.hpp>

namespace holo {

// True when a header other than `image` refers to the image's buffer (its reference count exceeds
// 1). Read atomically: another thread may be letting its reference go (cv::Mat releases by an
// atomic decrement). Once the count reads 1 nobody else can take a reference, and the acquire
// orders that thread's last reads of the pixels before the writes that follow. An empty image or
// one over foreign memory: false.
inline bool sharedElsewhere(const cv::Mat& image) {
  return image.u != nullptr && __atomic_load_n(&image.u->refcount, __ATOMIC_ACQUIRE) > 1;
}

}  // namespace holo
