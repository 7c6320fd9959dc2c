// Temporal persistence of the foreground mask where the sensor reads nothing. A depth sensor
// drops a visitor's pixels at grazing angles, on dark hair and clothes and at random; there the
// foreground mask falls back to colour, which misses a visitor whose colour is close to the
// background's. Such a pixel stays foreground when
//   * its depth is missing (0/NaN/Inf) in this frame,
//   * its precursor px + flow(px) was foreground in the previous frame's (extended) mask, and
//   * its colour is within `colour_max` (sum of |B|, |G|, |R| differences, 0..765) of the
//     precursor's colour: the colour camera still sees the same surface there.
// Where the depth is valid the depth decided and nothing changes, so a visitor who leaves is
// released as soon as the sensor reads the hall again, and where it does not, as soon as the
// colour there is no longer the visitor's (the wall behind a visitor who walked off, the
// projector's shadow on the wall). The filter downstream still decides whether such a pixel is
// filled; unfilled, it is a hole like before.
//
// Units: pixels; flow CV_32FC2 current -> previous. Invariant: the mask only grows, and only on
// pixels without depth.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/rgbd_frame.hpp"

namespace holo::depthfilter {

struct MaskPersistenceConfig {
  bool enabled = true;
  float colour_max = 30.0f;  // sum of absolute B, G, R differences to the precursor (0..765)
  // Only pixels within this many pixels of the previous mask's bounding box are looked at (a
  // precursor farther away is an image motion faster than a visitor's; it bounds the work).
  int max_motion_px = 32;
};

class MaskPersistence {
 public:
  // Throws holo::Error when colour_max is outside [0, 765] or max_motion_px is negative.
  explicit MaskPersistence(MaskPersistenceConfig config = {});

  // Extends `mask` (CV_8UC1, 255 = foreground, changed in place) for `frame` with the flow to the
  // previous frame, and remembers the result and the frame's colour for the next frame.
  // An empty flow (first frame) changes nothing. Throws holo::Error on mismatched types or sizes.
  void extend(cv::Mat& mask, const RgbdFrame& frame, const cv::Mat& flow);
  // Forgets the previous frame (a camera dropped out).
  void reset();
  // The pixels the next extend() on a frame of `size` may add to the mask, and so the only ones
  // where it reads the flow: the previous mask's box grown by max_motion_px (empty when switched
  // off, without a previous frame of that size, or when its mask was empty).
  cv::Rect searchBox(const cv::Size& size) const;

  const MaskPersistenceConfig& config() const { return config_; }

 private:
  MaskPersistenceConfig config_;
  cv::Mat previous_mask_, previous_colour_;
  cv::Rect previous_box_;  // bounding box of previous_mask_
};

}  // namespace holo::depthfilter
