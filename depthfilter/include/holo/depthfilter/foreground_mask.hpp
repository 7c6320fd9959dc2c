// Foreground mask phi_i of one camera (paper Sec. 3.2): OpenCV's MOG2 on colour, combined with a
// per-pixel background depth. Both models are learned from the background frames gamma_s and
// updated live only where the pixel is judged background, so a visitor who stands still stays
// foreground while the depth says they stand in front of the hall.
//
// Decision per pixel (depth in metres, margin(z) = depth_margin_m + depth_margin_z2 * z^2):
//   * static foreground (the pyramid's own pixels, from the configuration): always foreground;
//   * current and background depth valid: foreground iff depth < background - margin; colour is
//     ignored there, so a shadow, a reflection or a global brightness change on a surface at the
//     background's depth never counts, and a visitor whose colour matches the wall still does;
//   * otherwise (no depth here or no background depth learned): MOG2's colour decision, with
//     MOG2's shadow label counted as background (where the sensor reads a depth but none was
//     learned for the background, the colour labels before the downscaled model's shrink).
// A pixel without a learned background depth adopts a live one only after it has held for
// background_adopt_frames readings judged background in a row.
// The result is cleaned by a morphological opening (undone on regions that keep a pixel through
// it, keep_attached_limbs) and a closing, then grown into readings of unknown background depth
// that continue its surface (unknown_background_growth_steps). Output: CV_8UC1, 255 = foreground.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/video/background_segm.hpp>
#include <vector>

#include "holo/core/rgbd_frame.hpp"

namespace holo::depthfilter {

struct ForegroundMaskConfig {
  int mog2_history = 500;                  // frames MOG2 remembers
  double mog2_var_threshold = 16.0;        // squared Mahalanobis distance for "matches the model"
  bool detect_shadows = true;              // MOG2 labels shadows 127; they count as background
  double learning_rate_background = -1.0;  // while learning gamma_s (-1: MOG2's automatic 1/n)
  double learning_rate_live = 0.001;       // live update; ~1000 frames to absorb a change
  float depth_margin_m = 0.04f;            // constant part of the "clearly in front" margin, metres
  float depth_margin_z2 = 0.0075f;         // grows with z^2 like depth-sensor noise, 1/metres
  float background_depth_rate = 0.02f;     // live exponential update of background depth
  // Where the empty hall read no depth, a live reading becomes the background depth only after
  // this many readings in a row judged background and within the margin of each other (1: at
  // once). A visitor's edge that the colour missed, adopted at once, hid the visitor there after.
  static constexpr int kMaxBackgroundAdoptFrames = 1000;
  int background_adopt_frames = 30;
  // Where the sensor reads a depth but the background's is unknown, the colour labels before the
  // shrink of the downscaled model decide (the shrink removes overhangs only where nothing is read).
  bool unshrunk_colour_over_unread_background = true;
  int open_radius = 1;  // pixels; removes isolated noise
  // After the opening, every connected region of the unopened mask that kept a pixel through it
  // comes back whole: specks still go, thin limbs joined to a body return.
  bool keep_attached_limbs = true;
  int close_radius = 2;  // pixels; closes small gaps inside a visitor
  // After the clean-up, the mask grows by up to this many pixels into readings whose background
  // depth is unknown and that continue a touching mask pixel's surface within the depth margin
  // (mask_depth_growth.hpp). 0: off. 8 by measurement on the halls (docs/depthfilter.md).
  int unknown_background_growth_steps = 8;
  // MOG2 runs on the colour frame downscaled by this factor (area average) and its labels are
  // scaled back (nearest). Colour decides only where depth is missing, so half resolution costs
  // little there and saves 3/4 of MOG2's time (docs/depthfilter.md, "Speed"). 1 = full size.
  int colour_model_downscale = 2;
  cv::Mat static_foreground;  // optional CV_8UC1, non-zero = pyramid pixel, never background
};

class ForegroundMasker {
 public:
  explicit ForegroundMasker(ForegroundMaskConfig config = {});

  // Adds one background frame gamma_s (no visitors). Depth 0/NaN/Inf pixels are ignored.
  // Throws holo::Error when the frame's size differs from earlier frames.
  void learnBackground(const RgbdFrame& frame);
  int backgroundFrames() const { return background_frames_; }

  // Foreground mask of a live frame, and the live update of both background models.
  // Works before any background frame (then everything new to MOG2 is foreground).
  cv::Mat apply(const RgbdFrame& frame);

  // Per-pixel background depth (CV_32FC1, 0 = unknown).
  const cv::Mat& backgroundDepth() const { return background_depth_; }
  const ForegroundMaskConfig& config() const { return config_; }

 private:
  void checkSize(const RgbdFrame& frame);
  const cv::Mat& colourForModel(const cv::Mat& colour);  // the frame MOG2 sees
  void reconstructInside(cv::Mat& opened);               // keep_attached_limbs

  ForegroundMaskConfig config_;
  cv::Ptr<cv::BackgroundSubtractorMOG2> mog2_;
  cv::Mat background_depth_;        // CV_32FC1, running mean of valid background depth
  cv::Mat background_depth_count_;  // CV_32FC1, samples in the mean while learning
  // Where the background depth is unknown: the live reading being adopted (CV_32FC1, the mean of
  // the run) and the length of its run of background readings (CV_16UC1).
  cv::Mat adopt_candidate_, adopt_count_;
  int background_frames_ = 0;
  cv::Mat small_colour_, colour_labels_;  // scratch, reused across frames
  // Scratch of a downscaled colour model: its foreground (255), at full size, shrunk.
  cv::Mat small_colour_foreground_, upsampled_colour_foreground_, colour_foreground_;
  cv::Mat unopened_, region_labels_;  // scratch of keep_attached_limbs
  cv::Mat growth_scratch_;            // scratch of the growth into unknown background
  std::vector<std::uint8_t> kept_region_;
};

}  // namespace holo::depthfilter
