#include "holo/depthfilter/mask_depth_growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "depth_validity.hpp"
#include "holo/core/error.hpp"

namespace holo::depthfilter {

void growMaskIntoUnknownBackground(cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const MaskDepthGrowthConfig& config, cv::Mat& scratch) {
  if (config.steps <= 0) return;
  if (mask.type() != CV_8UC1 || depth.type() != CV_32FC1 || background_depth.type() != CV_32FC1 ||
      mask.size() != depth.size() || mask.size() != background_depth.size())
    throw Error("growMaskIntoUnknownBackground: expected CV_8UC1 mask and CV_32FC1 depths of one size");
  const cv::Rect box = cv::boundingRect(mask);
  if (box.empty()) return;
  // Growth reaches at most `steps` pixels past the mask's bounding box; the pixels it may take
  // (a reading, no background depth, not yet in the mask) are listed once, then each step looks
  // only at those.
  const cv::Rect region = cv::Rect(box.x - config.steps, box.y - config.steps, box.width + 2 * config.steps,
                                   box.height + 2 * config.steps) &
                          cv::Rect(0, 0, mask.cols, mask.rows);
  // scratch holds the candidates' indices, then room for those that join in one step.
  scratch.create(1, 2 * region.area(), CV_32SC1);
  int* const candidates = scratch.ptr<int>();
  int* const joined = candidates + region.area();
  int count = 0;
  for (int y = region.y; y < region.y + region.height; ++y) {
    const float* d = depth.ptr<float>(y);
    const float* bg = background_depth.ptr<float>(y);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    for (int x = region.x; x < region.x + region.width; ++x)
      if (m[x] == 0 && validDepth(d[x]) && !validDepth(bg[x])) candidates[count++] = y * mask.cols + x;
  }
  const int cols = mask.cols, rows = mask.rows;
  const float margin_m = config.depth_margin_m, margin_z2 = config.depth_margin_z2;
  // A candidate joins from a mask neighbour with a reading on the same surface.
  const auto continues = [&](float z, int y, int x) {
    if (mask.ptr<std::uint8_t>(y)[x] == 0) return false;
    const float zn = depth.ptr<float>(y)[x];
    return validDepth(zn) && std::abs(z - zn) <= margin_m + margin_z2 * z * z;
  };
  for (int step = 0; step < config.steps && count > 0; ++step) {
    // This step reads the mask as the last step left it: joins are written after the pass.
    int joins_now = 0, kept = 0;
    for (int c = 0; c < count; ++c) {
      const int i = candidates[c];
      const int x = i % cols, y = i / cols;
      const float z = depth.ptr<float>(y)[x];
      const bool joins = (x > 0 && continues(z, y, x - 1)) || (x + 1 < cols && continues(z, y, x + 1)) ||
                         (y > 0 && continues(z, y - 1, x)) || (y + 1 < rows && continues(z, y + 1, x));
      if (joins)
        joined[joins_now++] = i;
      else
        candidates[kept++] = i;
    }
    if (joins_now == 0) return;
    count = kept;
    for (int j = 0; j < joins_now; ++j) mask.ptr<std::uint8_t>(joined[j] / cols)[joined[j] % cols] = 255;
  }
}

}  // namespace holo::depthfilter
