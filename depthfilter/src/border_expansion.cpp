#include "holo/depthfilter/border_expansion.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "depth_validity.hpp"
#include "holo/core/error.hpp"

namespace holo::depthfilter {

namespace {

// The mask as 0/1 floats over `region` (a fresh image, so that the pyramid reflects its own
// border, not the frame's pixels beyond it).
cv::Mat maskLevel(const cv::Mat& mask, const cv::Rect& region) {
  cv::Mat level(region.size(), CV_32FC1);
  for (int y = 0; y < region.height; ++y) {
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(y + region.y) + region.x;
    float* __restrict l = level.ptr<float>(y);
    // Any non-zero value is foreground; a converted bool rather than ?: keeps the loop vectorised.
    for (int x = 0; x < region.width; ++x) l[x] = float(m[x] != 0);
  }
  return level;
}

cv::Mat pyramidTopAtSize(cv::Mat level, int levels, const cv::Size& size) {
  for (int l = 0; l < levels && level.cols > 1 && level.rows > 1; ++l) cv::pyrDown(level, level);
  cv::Mat full;
  cv::resize(level, full, size, 0, 0, cv::INTER_LINEAR);
  return full;
}

// The blurred mask (the top of a `levels`-deep Gaussian pyramid of the mask brought back to the
// frame's size) over `needed`, which holds the mask's bounding box `box`. Where the frame's sides
// are multiples of the pyramid's cell (2^levels px), only a cell-aligned region around `needed` is
// blurred: the blur spreads the mask less than 3 cells, so the region's border, 6 cells or more
// from the box, lies where the whole frame's pyramid is 0, and what the region's own border
// reflection reads there is 0 too; the resize by exactly the cell maps each pixel to the same
// coarse pixels and weights. The values are the whole frame's, bit for bit.
cv::Mat blurredMask(const cv::Mat& mask, int levels, const cv::Rect& box, const cv::Rect& needed) {
  const cv::Rect frame(0, 0, mask.cols, mask.rows);
  const int cell = 1 << std::min(levels, 10);
  if (mask.cols % cell != 0 || mask.rows % cell != 0)
    return pyramidTopAtSize(maskLevel(mask, frame), levels, mask.size())(needed).clone();
  const int margin = 6 * cell;
  const int x0 = std::max(0, std::min(needed.x, box.x - margin) / cell * cell);
  const int y0 = std::max(0, std::min(needed.y, box.y - margin) / cell * cell);
  const int x1 = std::min(mask.cols, (std::max(needed.br().x, box.br().x + margin) + cell - 1) / cell * cell);
  const int y1 = std::min(mask.rows, (std::max(needed.br().y, box.br().y + margin) + cell - 1) / cell * cell);
  const cv::Rect region(x0, y0, x1 - x0, y1 - y0);
  return pyramidTopAtSize(maskLevel(mask, region), levels, region.size())(needed - region.tl());
}

// Mean filtered depth over foreground pixels that touch the background (4-neighbourhood).
float meanEdgeDepth(const cv::Mat& mask, const cv::Mat& depth) {
  double sum = 0.0;
  long count = 0;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      if (mask.at<std::uint8_t>(y, x) == 0 || !validDepth(depth.at<float>(y, x))) continue;
      const bool edge = (x == 0 || mask.at<std::uint8_t>(y, x - 1) == 0) ||
                        (x + 1 == mask.cols || mask.at<std::uint8_t>(y, x + 1) == 0) ||
                        (y == 0 || mask.at<std::uint8_t>(y - 1, x) == 0) ||
                        (y + 1 == mask.rows || mask.at<std::uint8_t>(y + 1, x) == 0);
      if (!edge) continue;
      sum += depth.at<float>(y, x);
      ++count;
    }
  return count > 0 ? float(sum / double(count)) : 0.0f;
}

}  // namespace

cv::Rect borderBox(const cv::Mat& mask, const BorderExpansionConfig& config) {
  const cv::Rect box = cv::boundingRect(mask);
  if (box.empty()) return box;
  // Border pixels lie within reach of the blurred mask: the Gaussian pyramid spreads the mask by
  // 2 px per level at that level's scale (2^(levels+1) - 2 px in all), and the upsampling by
  // about one coarse pixel more (2^levels), so less than 4 * 2^levels px.
  const int reach = config.levels > 0 ? 4 << std::min(config.levels, 10) : 0;
  return cv::Rect(box.x - reach, box.y - reach, box.width + 2 * reach, box.height + 2 * reach) &
         cv::Rect(0, 0, mask.cols, mask.rows);
}

BorderLayer expandBorder(const cv::Mat& mask, const cv::Mat& depth, const BorderExpansionConfig& config) {
  ReusedZeroImage weight_image, depth_image;
  return expandBorder(mask, depth, config, weight_image, depth_image);
}

BorderLayer expandBorder(const cv::Mat& mask, const cv::Mat& depth, const BorderExpansionConfig& config,
                         ReusedZeroImage& weight_image, ReusedZeroImage& depth_image) {
  if (mask.type() != CV_8UC1 || depth.type() != CV_32FC1 || mask.size() != depth.size())
    throw Error("expandBorder: expected a CV_8UC1 mask and CV_32FC1 depth of one size");
  BorderLayer layer{weight_image.next(mask.size(), CV_32FC1), depth_image.next(mask.size(), CV_32FC1)};
  if (config.levels <= 0 || mask.empty()) return layer;
  // Everything below works on the border box (empty when the mask is), and writes inside it only.
  const cv::Rect roi = borderBox(mask, config);
  if (roi.empty()) return layer;
  weight_image.written(roi);
  depth_image.written(roi);
  const cv::Mat mask_roi = mask(roi), depth_roi = depth(roi);

  // Foreground pixels with a valid depth, the sources of border depth, are 0 here (as
  // distanceTransform wants them), every other pixel 255.
  cv::Mat not_sources(roi.size(), CV_8UC1);
  int source_count = 0;
  for (int y = 0; y < roi.height; ++y) {
    const std::uint8_t* m = mask_roi.ptr<std::uint8_t>(y);
    const float* d = depth_roi.ptr<float>(y);
    std::uint8_t* s = not_sources.ptr<std::uint8_t>(y);
    for (int x = 0; x < roi.width; ++x) {
      const bool source = m[x] != 0 && validDepth(d[x]);
      s[x] = source ? 0 : 255;
      source_count += source;
    }
  }
  if (source_count == 0) return layer;

  const cv::Mat blurred = blurredMask(mask, config.levels, cv::boundingRect(mask), roi);
  float mean_edge = 0.0f;
  cv::Mat nearest_labels;
  std::vector<cv::Point> label_pixel;
  if (config.depth == BorderDepth::MeanEdge) {
    mean_edge = meanEdgeDepth(mask, depth);
    if (!(mean_edge > 0.0f)) return layer;
  } else {
    // distanceTransform labels every pixel with the nearest zero pixel of its input, so the input
    // is zero exactly on the depth sources.
    cv::Mat distance;
    cv::distanceTransform(not_sources, distance, nearest_labels, cv::DIST_L2, cv::DIST_MASK_5,
                          cv::DIST_LABEL_PIXEL);
    label_pixel.resize(std::size_t(source_count) + 1);
    for (int y = 0; y < roi.height; ++y) {
      const std::uint8_t* s = not_sources.ptr<std::uint8_t>(y);
      const int* label = nearest_labels.ptr<int>(y);
      for (int x = 0; x < roi.width; ++x)
        if (s[x] == 0) label_pixel[std::size_t(label[x])] = {x, y};
    }
  }

  for (int y = 0; y < roi.height; ++y) {
    const std::uint8_t* m = mask_roi.ptr<std::uint8_t>(y);
    const float* weight = blurred.ptr<float>(y);
    float* out_weight = layer.weight.ptr<float>(y + roi.y) + roi.x;
    float* out_depth = layer.depth.ptr<float>(y + roi.y) + roi.x;
    for (int x = 0; x < roi.width; ++x) {
      if (m[x] != 0) continue;
      const float w = weight[x];
      if (!(w >= config.min_weight) || w >= 1.0f) continue;
      float d = mean_edge;
      if (config.depth == BorderDepth::Nearest) {
        const cv::Point p = label_pixel[std::size_t(nearest_labels.ptr<int>(y)[x])];
        d = depth_roi.ptr<float>(p.y)[p.x];
      }
      if (!validDepth(d)) continue;
      out_weight[x] = w;
      out_depth[x] = d;
    }
  }
  return layer;
}

}  // namespace holo::depthfilter
