#include "holo/depthfilter/full_size_outline.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

FullSizeForeground fullSizeOutline(const cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const cv::Mat& camera_depth, int scale,
                                   const FullSizeOutlineConfig& config) {
  ReusedZeroImage mask_image, depth_image;
  return fullSizeOutline(mask, depth, background_depth, camera_depth, scale, config, mask_image, depth_image);
}

FullSizeForeground fullSizeOutline(const cv::Mat& mask, const cv::Mat& depth, const cv::Mat& background_depth,
                                   const cv::Mat& camera_depth, int scale,
                                   const FullSizeOutlineConfig& config, ReusedZeroImage& mask_image,
                                   ReusedZeroImage& depth_image) {
  if (mask.type() != CV_8UC1 || depth.type() != CV_32FC1 || background_depth.type() != CV_32FC1 ||
      camera_depth.type() != CV_32FC1 || scale < 1 || depth.size() != mask.size() ||
      background_depth.size() != mask.size() || camera_depth.size() != mask.size() * scale)
    throw Error(
        "fullSizeOutline: expected a CV_8UC1 mask, CV_32FC1 depth and background depth of one size and "
        "CV_32FC1 camera depth of that size times the scale");
  FullSizeForeground out{mask_image.next(camera_depth.size(), CV_8UC1),
                         depth_image.next(camera_depth.size(), CV_32FC1),
                         cv::Mat::zeros(mask.size(), CV_8UC1)};
  const cv::Rect mask_box = cv::boundingRect(mask);
  if (mask_box.empty()) return out;
  const cv::Rect box = cv::Rect(mask_box.x - 1, mask_box.y - 1, mask_box.width + 2, mask_box.height + 2) &
                       cv::Rect(0, 0, mask.cols, mask.rows);
  const cv::Rect written(box.x * scale, box.y * scale, box.width * scale, box.height * scale);
  mask_image.written(written);
  depth_image.written(written);
  for (int by = box.y; by < box.y + box.height; ++by) {
    const int y0 = std::max(by - 1, 0), y1 = std::min(by + 1, mask.rows - 1);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(by);
    const float* d = depth.ptr<float>(by);
    const float* background = background_depth.ptr<float>(by);
    for (int bx = box.x; bx < box.x + box.width; ++bx) {
      const int x0 = std::max(bx - 1, 0), x1 = std::min(bx + 1, mask.cols - 1);
      const bool foreground = m[bx] != 0;
      bool outline = false;
      float nearest_depth = std::numeric_limits<float>::infinity(), farthest_depth = 0.0f;
      for (int ny = y0; ny <= y1; ++ny) {
        const std::uint8_t* nm = mask.ptr<std::uint8_t>(ny);
        const float* nd = depth.ptr<float>(ny);
        for (int nx = x0; nx <= x1; ++nx) {
          outline |= (nm[nx] != 0) != foreground;
          if (nm[nx] != 0 && nd[nx] > 0.0f) {
            nearest_depth = std::min(nearest_depth, nd[nx]);
            farthest_depth = std::max(farthest_depth, nd[nx]);
          }
        }
      }
      // Inside the foreground, a block beside another surface (an arm before the body) is split
      // by the readings too; there a reading near none of them keeps the block's depth.
      const bool depth_edge =
          !outline && farthest_depth - nearest_depth >
                          config.depth_margin_m + config.depth_margin_z2 * nearest_depth * nearest_depth;
      if (outline || depth_edge) out.redrawn.at<std::uint8_t>(by, bx) = 255;
      const std::uint8_t block_mask = foreground ? 255 : 0;
      const float block_depth = d[bx];
      const float bg = background[bx];
      // A reading at or behind this is the hall (the mask's own test; none where bg is unknown).
      const float hall = bg > 0.0f ? bg - (config.depth_margin_m + config.depth_margin_z2 * bg * bg)
                                   : std::numeric_limits<float>::infinity();
      for (int y = by * scale; y < (by + 1) * scale; ++y) {
        std::uint8_t* om = out.mask.ptr<std::uint8_t>(y);
        float* od = out.depth.ptr<float>(y);
        const float* z = camera_depth.ptr<float>(y);
        for (int x = bx * scale; x < (bx + 1) * scale; ++x) {
          om[x] = block_mask;
          od[x] = block_depth;
          const float reading = z[x];
          if (!(outline || depth_edge) || !(reading > 0.0f) || !std::isfinite(reading)) continue;
          if (reading >= hall) {
            om[x] = 0;
            od[x] = 0.0f;
            continue;
          }
          float nearest = 0.0f, nearest_gap = std::numeric_limits<float>::infinity();
          for (int ny = y0; ny <= y1; ++ny) {
            const std::uint8_t* nm = mask.ptr<std::uint8_t>(ny);
            const float* nd = depth.ptr<float>(ny);
            for (int nx = x0; nx <= x1; ++nx) {
              const float gap = std::abs(nd[nx] - reading);
              if (nm[nx] != 0 && nd[nx] > 0.0f && gap < nearest_gap) {
                nearest = nd[nx];
                nearest_gap = gap;
              }
            }
          }
          if (!(nearest > 0.0f)) continue;
          const bool same_surface =
              nearest_gap <= config.depth_margin_m + config.depth_margin_z2 * reading * reading;
          if (depth_edge && !same_surface) continue;
          om[x] = same_surface ? 255 : 0;
          od[x] = same_surface ? nearest : 0.0f;
        }
      }
    }
  }
  return out;
}

}  // namespace holo::depthfilter
