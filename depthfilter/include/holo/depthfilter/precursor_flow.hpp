// Optical flow lambda_i of one camera (paper Sec. 3.2) with OpenCV's DIS optical flow. The flow is
// computed backwards, from the current frame to the previous one, so that every current pixel px
// directly indexes its precursor px_pre = px + lambda_i(px) in the previous frame (the pixel that
// showed the same real content). Units: pixels. Output CV_32FC2, finite everywhere except, with
// the round-trip check, NaN at the pixels whose precursor it rejects (every user treats a
// non-finite vector as "no precursor").
#pragma once

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {

struct PrecursorFlowConfig {
  // cv::DISOpticalFlow::PRESET_ULTRAFAST, PRESET_FAST or PRESET_MEDIUM. ULTRAFAST by measurement
  // (docs/depthfilter.md, "Optical flow preset"): on the moving-disc sequence its end-point error
  // is 0.20 px (FAST 0.34, MEDIUM 0.03) at 2.4 ms per 640x360 frame (FAST 4.2, MEDIUM 22.5), and
  // precursors are rounded to whole pixels, so MEDIUM's accuracy buys nothing.
  int preset = cv::DISOpticalFlow::PRESET_ULTRAFAST;
  // The flow is computed on frames downscaled by this factor (area average) and scaled back
  // (bilinear, vectors times the factor). 1 = full size. See docs/depthfilter.md, "Speed".
  int downscale = 2;
  // The forward-backward check: the flow is also computed forwards (previous -> current, on the
  // same downscaled images) and a pixel px whose precursor q = px + lambda(px) does not map back
  // to it (|lambda(px) + forward(q)| above round_trip_max_px, in full-size pixels) has none: what
  // it shows was hidden in the previous frame (a disocclusion), so the previous depth there is
  // another surface's. Costs a second DIS flow.
  bool round_trip_check = false;
  float round_trip_max_px = 2.0f;
};

class PrecursorFlow {
 public:
  explicit PrecursorFlow(PrecursorFlowConfig config = {});

  // Flow from `current` to `previous` (both CV_8UC3 BGR of one size): previous(px + flow(px))
  // shows what current(px) shows. Zero flow when `previous` is empty (the first frame).
  cv::Mat compute(const cv::Mat& current_bgr, const cv::Mat& previous_bgr);
  // The same flow from `current` to the frame of the previous next() call, whose grey (downscaled)
  // image is kept instead of being made again from its colour; zero flow on the first frame, after
  // reset() or when the size changed.
  cv::Mat next(const cv::Mat& current_bgr);
  // The same flow, guaranteed only inside `needed` (the values compute() gives there), for users
  // that read it near the foreground only: with the default downscale 2 and even frame sides only
  // those pixels are brought to full size and the rest is 0; otherwise the whole frame is computed.
  // Nothing is computed (all 0) when `needed` is empty.
  cv::Mat next(const cv::Mat& current_bgr, const cv::Rect& needed);
  void reset();  // the next frame is a first frame

 private:
  // The grey image the flow is computed on (downscaled), into `out`.
  void flowImage(const cv::Mat& bgr, cv::Mat& out);
  // The flow between two flow images of a full-size frame `size`, exact inside `needed` (see next()).
  cv::Mat flowBetween(const cv::Mat& current, const cv::Mat& previous, const cv::Size& size,
                      const cv::Rect& needed);
  cv::Mat nextFlow(const cv::Mat& current_bgr, const cv::Rect& needed);
  // The downscaled flow brought to full size (bilinear) inside `needed` only, into `flow` (0
  // elsewhere), each pixel equal to a whole-frame cv::resize's.
  void upsampleInside(const cv::Rect& needed, cv::Mat& flow);

  // NaN where the forward flow does not bring the precursor back (round_trip_check), inside `needed`.
  void rejectRoundTripFailures(const cv::Mat& current, const cv::Mat& previous, const cv::Rect& needed,
                               cv::Mat& flow);

  cv::Ptr<cv::DISOpticalFlow> dis_;
  int downscale_ = 1;
  bool round_trip_check_ = false;
  float round_trip_max_px_ = 2.0f;
  cv::Mat grey_, current_image_, previous_image_, small_flow_, forward_flow_, upsampled_block_;  // scratch
  ReusedZeroImage upsampled_flow_;  // the flow next() returns, zero outside `needed`
  cv::Size previous_size_;          // of the frame previous_image_ was made from; empty: none (next())
};

// Confidence alpha of Equation 1: the RGB distance between a pixel and its precursor, in 8-bit
// sRGB steps, in [0, sqrt(3) * 255]. Smaller means a more reliable precursor. Inline: the filter
// calls it once per foreground pixel.
inline float precursorConfidence(const cv::Vec3b& pixel, const cv::Vec3b& precursor) {
  float sum = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const float diff = float(pixel[c]) - float(precursor[c]);
    sum += diff * diff;
  }
  return std::sqrt(sum);
}

// The whole pixel nearest to coordinate `v` (halves away from zero, as std::lround) for a finite
// `v`; coordinates beyond +-2^24 px, far outside any frame, come back as +-2^24. Inline and without
// errno, unlike std::lround: every foreground pixel rounds its precursor.
inline int nearestPixel(float v) {
  constexpr float kFar = 16777216.0f;
  v = std::min(std::max(v, -kFar), kFar);
  const int toward_zero = static_cast<int>(v);
  const float rest = v - static_cast<float>(toward_zero);  // exact: |v| <= 2^24
  return toward_zero + (rest >= 0.5f) - (rest <= -0.5f);
}

}  // namespace holo::depthfilter
