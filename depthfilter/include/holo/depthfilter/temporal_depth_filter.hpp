// The pull-push temporal depth filter of one camera (paper Sec. 3.2, Algorithm 1). It fills and
// filters the depth of the foreground pixels of the current frame gamma_i using the previous
// frame's filtered depth gamma_{i-1}, reached through the optical flow lambda_i.
//
// Measurements first lose flying pixels: a depth with fewer than `min_support` of its 8
// neighbours on its surface counts as missing. Per foreground pixel px with precursor
// px_pre = px + lambda_i(px), whose depth is shifted by the local mean depth change (the motion
// in depth that the image flow does not carry):
//   alpha = |rgb(px) - rgb(px_pre)| (Equation 1), |d| = |px.d - px_pre.d|,
//   during the first C frames: only PDF_alpha and PDF_|d| learn, the frame passes unfiltered;
//   afterwards: d_hat = (1 - P_|d|) px.d + P_|d| px_pre.d with confidence c = P_alpha,
//   where P_x = P(X <= x) of the learned distribution (smaller c = more reliable).
// Pull, depth-aware: level l+1 holds, per 2x2 block of level l, the weighted mean of the
// block's pairs on its dominant surface (the depth whose agreeing pairs, within the same-surface
// tolerance T(z), weigh most; a pair weighs 1 - c/2 at full resolution and the sum of its
// children above), so a block between a limb and the wall behind it takes the limb's depth or
// the wall's, never a depth between them, and is marked as straddling a depth edge. Push: from
// the top level down, a pixel without a pair takes the bilinear, weight-weighted mean of its
// four nearest parents only when they all lie on one surface and none straddles a depth edge
// (the hole's neighbourhood agrees); a pixel with a pair is blended with its parent by their
// reliabilities (1 - c) unless their depths differ by more than T(z) (a depth edge, kept sharp).
// Only foreground pixels (phi_i) receive output. A hole (a foreground pixel without a
// measurement) whose precursor was measured within the last `fill_trust_frames` frames takes the
// surface of its measured neighbours within `fill_radius` that share its colour, if those lie on
// the precursor's surface (see guidedHoleFill in the source). A hole without such a precursor is filled only
// away from depth edges: from those neighbours (all on one surface) where it has some, else, away from the
// mask's edge, with the push's fill where the mean colour of the measured pixels behind it (carried through
// the pyramid) is the hole's; but never when the first measurements left, right, above and below it inside
// the mask span a depth edge: it is a gap between two surfaces (between limbs) and may show a third one.
// A hole so left (its neighbours of its colour on two surfaces, next to a depth edge, between two surfaces or
// at the mask's edge) is filled when the frame comes with a SurfaceWitness (the other cameras): the surfaces
// of its neighbours of its colour are asked nearest first, and the first one the witness sees is taken, as
// long as every nearer one is seen through (any surface the witness cannot decide ends the search: a hole).
// Every other hole stays a hole. The choices where the paper is silent are listed, with reasons, in
// docs/depthfilter.md.
//
// Units: metres; depth 0 = invalid. Invariant: the output is CV_32FC1, finite, 0 outside phi_i,
// and every foreground value is either 0 (nothing within reach to fill from) or positive.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>

#include "holo/depthfilter/empirical_cdf.hpp"
#include "holo/depthfilter/hole_reason.hpp"
#include "holo/depthfilter/surface_witness.hpp"

namespace holo::depthfilter {

struct TemporalDepthFilterConfig {
  // l_max, levels including full resolution (1..kMaxLevels); the push reaches holes up to about
  // 2^l_max px across. 1 turns the pull-push off (holes are then left to the colour-guided hole
  // fill). Each level's gain on the simulated halls is in docs/depthfilter.md.
  static constexpr int kMaxLevels = 8;
  int levels = 3;
  int learning_frames = 30;                  // C: frames that only learn the PDFs (1 s at 30 fps)
  std::int64_t min_learning_samples = 1000;  // learning also lasts until each PDF has this many
  int pdf_bins = 256;                        // discrete values of each PDF
  float alpha_max = 441.68f;                 // PDF_alpha domain: the largest RGB distance, sqrt(3) * 255
  float depth_diff_max_m = 0.5f;             // PDF_|d| domain; larger differences count as the maximum
  // Same-surface tolerance T(z) = surface_tolerance_m + surface_tolerance_z2 * z^2 (metres, like
  // depth noise). A precursor farther than T in depth shows another surface (occlusion, fast
  // motion in depth) and is not used, so the filter cannot freeze a surface that moves; in the
  // push, a parent farther than T is across a depth edge and not blended, so edges stay sharp.
  float surface_tolerance_m = 0.03f;
  float surface_tolerance_z2 = 0.0075f;  // 1/metres
  // A measured depth needs this many of its 8 neighbours within T(z), else it is a flying pixel
  // (between two surfaces) or a speck and is treated as missing.
  int min_support = 2;
  // Side (pixels) of the window whose mean depth change d - d_pre is added to d_pre: the motion
  // in depth that the image flow cannot see. 1 turns it off.
  int motion_window = 9;
  // A hole whose measured neighbours within this radius (pixels) span a depth edge stays a hole.
  int edge_radius = 2;
  // Hole fill. A hole's precursor is trusted when its depth was measured at most
  // fill_trust_frames - 1 frames before (0 turns trust off). The push fills a hole unless it is
  // next to a depth edge, it has a trusted precursor, or it is within edge_radius of the mask's
  // edge. Otherwise, with a trusted precursor, the hole takes the mean of the measured neighbours
  // within `fill_radius` px that lie on the precursor's surface and whose colour (sum of
  // |B|,|G|,|R| differences) is within `fill_colour_margin` of the closest one, which must be at
  // most `fill_colour_max`.
  int fill_trust_frames = 3;
  // A hole with a trusted precursor whose neighbours of its colour lie on two surfaces takes
  // those on the precursor's surface (false: it stays a hole). Off: 35-41% of such fills lie
  // farther than T(z) from the truth and they flicker (docs/depthfilter.md "Holes at the mask's
  // edge and the precursor's surface").
  bool fill_on_precursor_surface = false;
  // A hole within edge_radius of the mask's edge without a trusted precursor, away from depth
  // edges, takes the farthest of its measured neighbours of its colour when they all lie on one
  // surface (the surface turns away there), never the push's fill (false: it stays a hole).
  bool fill_mask_edge = true;
  // A hole the rules above leave, next to two surfaces of its colour, takes the surface that the
  // frame's SurfaceWitness (another camera's measured depth) sees there, every nearer one seen
  // through (false, or no witness: it stays a hole).
  bool fill_witnessed = true;
  static constexpr int kMaxFillRadius = 4;
  int fill_radius = 3;  // 0..kMaxFillRadius
  float fill_colour_max = 30.0f;
  float fill_colour_margin = 20.0f;
  // Work only on the mask's bounding box grown by the filter's reach (and aligned to the
  // pyramid's blocks): the output is the same, since every per-pixel pass reads at most that far
  // from a foreground pixel. false runs every pass over the whole frame (the reference that the
  // tests and the benchmark compare with).
  bool mask_box_only = true;
  // Record why each hole was left (TemporalDepthFilter::holeReasons); a diagnostic for
  // `eval depth`, off in the product.
  bool record_hole_reasons = false;

  float surfaceTolerance(float depth_m) const {
    return surface_tolerance_m + surface_tolerance_z2 * depth_m * depth_m;
  }
};

// Inputs of one frame of one camera. Colour CV_8UC3 BGR, depth CV_32FC1 metres (0/NaN/Inf =
// invalid), mask CV_8UC1 (non-zero = foreground), flow CV_32FC2 current -> previous.
struct DepthFilterInput {
  cv::Mat colour;
  cv::Mat depth;
  cv::Mat mask;
  cv::Mat flow;
  // The other cameras' view of this frame, asked about the holes the filter cannot decide alone;
  // nullptr: none. Must outlive apply().
  const SurfaceWitness* witness = nullptr;
};

class TemporalDepthFilter {
 public:
  explicit TemporalDepthFilter(TemporalDepthFilterConfig config = {});
  ~TemporalDepthFilter();
  TemporalDepthFilter(TemporalDepthFilter&&) noexcept;
  TemporalDepthFilter& operator=(TemporalDepthFilter&&) noexcept;

  // Filters one frame and remembers it (with its output depth) as gamma_{i-1} for the next.
  // Throws holo::Error on mismatched image types or sizes.
  cv::Mat apply(const DepthFilterInput& input);
  // Forgets the previous frame (a camera dropped out); the learned PDFs stay.
  void resetHistory();

  // With TemporalDepthFilterConfig::record_hole_reasons: the last frame's HoleReason per pixel
  // (CV_8UC1; None where it output a depth, outside the mask and while learning); empty otherwise.
  const cv::Mat& holeReasons() const;

  bool learning() const;
  std::int64_t frame() const { return frame_; }
  const EmpiricalCdf& confidencePdf() const { return pdf_alpha_; }
  const EmpiricalCdf& depthDifferencePdf() const { return pdf_depth_diff_; }
  const TemporalDepthFilterConfig& config() const { return config_; }

 private:
  TemporalDepthFilterConfig config_;
  EmpiricalCdf pdf_alpha_;
  EmpiricalCdf pdf_depth_diff_;
  std::int64_t frame_ = 0;  // frames seen, i - 1
  cv::Mat previous_colour_;
  cv::Mat previous_depth_;  // filtered output of the previous frame
  cv::Mat previous_mask_;
  cv::Mat previous_age_;  // CV_8UC1 frames since each previous output depth was measured, 255 = none
  // The previous frame's work box: previous_mask_ is 0 outside it, and previous_colour_,
  // previous_depth_ and previous_age_ hold that frame's values inside it only.
  cv::Rect previous_roi_;
  // Per-frame working images, kept so that a frame allocates (and page-faults) almost nothing.
  struct Scratch;
  std::unique_ptr<Scratch> scratch_ptr_;
};

}  // namespace holo::depthfilter
