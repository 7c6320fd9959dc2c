#include "holo/depthfilter/foreground_mask.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "depth_validity.hpp"
#include "holo/core/error.hpp"
#include "holo/depthfilter/mask_depth_growth.hpp"

namespace holo::depthfilter {

namespace {

// c ? a : b by the bits, so that a loop of such selects has no branch and vectorises (GCC turns
// a float ?: into a jump there).
float selectBits(bool c, float a, float b) {
  std::uint32_t bits_a, bits_b;
  std::memcpy(&bits_a, &a, sizeof a);
  std::memcpy(&bits_b, &b, sizeof b);
  const std::uint32_t take_a = 0u - std::uint32_t(c);
  const std::uint32_t bits = (bits_a & take_a) | (bits_b & ~take_a);
  float out;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

cv::Mat disc(int radius) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
}

}  // namespace

ForegroundMasker::ForegroundMasker(ForegroundMaskConfig config)
    : config_(std::move(config)),
      mog2_(cv::createBackgroundSubtractorMOG2(config_.mog2_history, config_.mog2_var_threshold,
                                               config_.detect_shadows)) {
  if (config_.colour_model_downscale < 1)
    throw Error("ForegroundMasker: colour_model_downscale must be >= 1");
  if (config_.background_adopt_frames < 1 ||
      config_.background_adopt_frames > ForegroundMaskConfig::kMaxBackgroundAdoptFrames)
    throw Error("ForegroundMasker: background_adopt_frames must be in [1, " +
                std::to_string(ForegroundMaskConfig::kMaxBackgroundAdoptFrames) + "]");
}

const cv::Mat& ForegroundMasker::colourForModel(const cv::Mat& colour) {
  if (config_.colour_model_downscale == 1) return colour;
  const int f = config_.colour_model_downscale;
  cv::resize(colour, small_colour_, cv::Size((colour.cols + f - 1) / f, (colour.rows + f - 1) / f), 0, 0,
             cv::INTER_AREA);
  return small_colour_;
}

void ForegroundMasker::checkSize(const RgbdFrame& frame) {
  if (frame.colour.type() != CV_8UC3 || frame.depth.type() != CV_32FC1 ||
      frame.colour.size() != frame.depth.size())
    throw Error("ForegroundMasker: expected CV_8UC3 colour and CV_32FC1 depth of one size");
  if (background_depth_.empty()) {
    background_depth_ = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
    background_depth_count_ = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
    adopt_candidate_ = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
    adopt_count_ = cv::Mat::zeros(frame.depth.size(), CV_16UC1);
  } else if (frame.depth.size() != background_depth_.size()) {
    throw Error("ForegroundMasker: frame size changed from " + std::to_string(background_depth_.cols) + "x" +
                std::to_string(background_depth_.rows) + " to " + std::to_string(frame.depth.cols) + "x" +
                std::to_string(frame.depth.rows));
  }
  if (!config_.static_foreground.empty() &&
      (config_.static_foreground.size() != frame.depth.size() || config_.static_foreground.type() != CV_8UC1))
    throw Error("ForegroundMasker: static_foreground must be CV_8UC1 of the frame's size");
}

void ForegroundMasker::learnBackground(const RgbdFrame& frame) {
  checkSize(frame);
  mog2_->apply(colourForModel(frame.colour), colour_labels_, config_.learning_rate_background);
  for (int y = 0; y < frame.depth.rows; ++y) {
    const float* d = frame.depth.ptr<float>(y);
    float* mean = background_depth_.ptr<float>(y);
    float* count = background_depth_count_.ptr<float>(y);
    for (int x = 0; x < frame.depth.cols; ++x) {
      if (!validDepth(d[x])) continue;
      count[x] += 1.0f;
      mean[x] += (d[x] - mean[x]) / count[x];
    }
  }
  ++background_frames_;
}

// Morphological reconstruction of the opened mask inside the unopened one: every 8-connected
// region of the unopened mask that kept at least one pixel through the opening comes back whole.
// An isolated speck loses all its pixels to the opening and stays away; a limb one or two pixels
// wide, joined to a body that survives, returns with it.
void ForegroundMasker::reconstructInside(cv::Mat& opened) {
  const int regions = cv::connectedComponents(unopened_, region_labels_, 8, CV_32S);
  kept_region_.assign(std::size_t(regions), 0);
  for (int y = 0; y < opened.rows; ++y) {
    const std::uint8_t* o = opened.ptr<std::uint8_t>(y);
    const int* label = region_labels_.ptr<int>(y);
    for (int x = 0; x < opened.cols; ++x)
      if (o[x]) kept_region_[std::size_t(label[x])] = 255;
  }
  kept_region_[0] = 0;  // the background's label
  for (int y = 0; y < opened.rows; ++y) {
    std::uint8_t* o = opened.ptr<std::uint8_t>(y);
    const int* label = region_labels_.ptr<int>(y);
    for (int x = 0; x < opened.cols; ++x) o[x] = kept_region_[std::size_t(label[x])];
  }
}

cv::Mat ForegroundMasker::apply(const RgbdFrame& frame) {
  checkSize(frame);
  mog2_->apply(colourForModel(frame.colour), colour_labels_, config_.learning_rate_live);
  const cv::Mat* colour_decision = &colour_labels_;
  if (colour_labels_.size() != frame.colour.size()) {
    // Nearest upsampling turns each small foreground pixel into a block that overhangs the
    // visitor's outline by up to downscale - 1 px; those overhangs, where the sensor has no
    // depth, were ghosts. Shrinking the upsampled foreground by that much removes them.
    cv::compare(colour_labels_, 255, small_colour_foreground_, cv::CMP_EQ);
    cv::resize(small_colour_foreground_, upsampled_colour_foreground_, frame.colour.size(), 0, 0,
               cv::INTER_NEAREST);
    const int side = 2 * (config_.colour_model_downscale - 1) + 1;
    cv::erode(upsampled_colour_foreground_, colour_foreground_,
              cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
    colour_decision = &colour_foreground_;
  }
  const cv::Mat& colour_mask = *colour_decision;
  // Where the empty hall read no depth, a reading now is decided by the colour labels before the
  // shrink: the shrink removes overhangs where the sensor reads nothing, and here it reads.
  const bool shrunk = colour_decision == &colour_foreground_;
  const cv::Mat& unread_colour =
      config_.unshrunk_colour_over_unread_background && shrunk ? upsampled_colour_foreground_ : colour_mask;

  // Both per-pixel loops are branch-free selects (the branches were unpredictable along a
  // visitor's outline and cost more than the arithmetic).
  cv::Mat mask(frame.depth.size(), CV_8UC1);
  const float margin_m = config_.depth_margin_m, margin_z2 = config_.depth_margin_z2;
  const int cols = mask.cols;
  for (int y = 0; y < mask.rows; ++y) {
    // restrict: a byte store may alias anything, which would keep the loop scalar.
    const float* __restrict d = frame.depth.ptr<float>(y);
    const float* __restrict bg = background_depth_.ptr<float>(y);
    const std::uint8_t* __restrict colour = colour_mask.ptr<std::uint8_t>(y);
    const std::uint8_t* __restrict colour_unread = unread_colour.ptr<std::uint8_t>(y);
    std::uint8_t* __restrict out = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < cols; ++x) {
      const bool read = validDepth(d[x]), known = validDepth(bg[x]);
      const bool nearer = d[x] < bg[x] - (margin_m + margin_z2 * bg[x] * bg[x]);
      const bool by_colour = colour[x] == 255;  // 127 = shadow -> background
      const bool by_unread_colour = colour_unread[x] == 255;
      out[x] = std::uint8_t(
          ((read & known & nearer) | (!read & by_colour) | (read & !known & by_unread_colour)) * 255);
    }
  }
  // Opening and closing change nothing farther than 2 * (open + close) radii from the
  // foreground: only that box around it is filtered (visitors cover a part of the frame).
  const int reach = 2 * (std::max(config_.open_radius, 0) + std::max(config_.close_radius, 0));
  const cv::Rect box = cv::boundingRect(mask);
  if (reach > 0 && !box.empty()) {
    cv::Mat roi = mask(cv::Rect(box.x - reach, box.y - reach, box.width + 2 * reach, box.height + 2 * reach) &
                       cv::Rect(0, 0, mask.cols, mask.rows));
    if (config_.open_radius > 0) {
      if (config_.keep_attached_limbs) roi.copyTo(unopened_);
      cv::morphologyEx(roi, roi, cv::MORPH_OPEN, disc(config_.open_radius));
      if (config_.keep_attached_limbs) reconstructInside(roi);
    }
    if (config_.close_radius > 0) cv::morphologyEx(roi, roi, cv::MORPH_CLOSE, disc(config_.close_radius));
  }
  growMaskIntoUnknownBackground(mask, frame.depth, background_depth_,
                                {config_.unknown_background_growth_steps, margin_m, margin_z2},
                                growth_scratch_);
  if (!config_.static_foreground.empty()) mask.setTo(255, config_.static_foreground);

  // Live update of the background depth where the pixel is background and the depth valid; a
  // pixel that sees farther than its background (a door opened) moves there at the same rate.
  // Where the background depth is unknown (the empty hall read nothing), a reading becomes it only
  // once it has held within the margin for background_adopt_frames readings judged background in
  // a row: adopted at once, the edge of a visitor that the colour missed became the background,
  // and the visitor was background there whenever it passed again.
  const float rate = config_.background_depth_rate;
  const int adopt_frames = config_.background_adopt_frames;
  for (int y = 0; y < mask.rows; ++y) {
    const float* __restrict d = frame.depth.ptr<float>(y);
    float* __restrict bg = background_depth_.ptr<float>(y);
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(y);
    // Where the background depth is known (nearly everywhere), a branch-free select that the
    // compiler vectorises; it leaves an unknown background as it was, so the adoption below
    // finds exactly the pixels it was unknown at.
    std::uint8_t any_unknown = 0;
    for (int x = 0; x < cols; ++x) {
      const float was = bg[x], now = d[x];
      const bool known = validDepth(was);
      bg[x] = selectBits(known & (m[x] == 0) & validDepth(now), was + rate * (now - was), was);
      any_unknown |= std::uint8_t(!known);
    }
    if (any_unknown == 0) continue;
    float* __restrict candidate = adopt_candidate_.ptr<float>(y);
    std::uint16_t* __restrict count = adopt_count_.ptr<std::uint16_t>(y);
    for (int x = 0; x < cols; ++x) {
      if (validDepth(bg[x])) continue;
      const float now = d[x];
      if (m[x] != 0) {
        count[x] = 0;  // something stands in front: start again
        continue;
      }
      if (!validDepth(now)) continue;
      const float c = candidate[x];
      if (count[x] > 0 && std::abs(now - c) <= margin_m + margin_z2 * c * c) {
        ++count[x];
        candidate[x] = c + (now - c) / float(count[x]);
      } else {
        count[x] = 1;
        candidate[x] = now;
      }
      if (count[x] >= adopt_frames) {
        bg[x] = candidate[x];
        count[x] = 0;
      }
    }
  }
  return mask;
}

}  // namespace holo::depthfilter
