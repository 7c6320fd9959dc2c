// Evaluation of the temporal depth filter against its baselines on sequences with known truth
// (paper Sec. 4.1.3, Table 2; `holopyramid eval depth`). Every method sees the same
// foreground mask (ForegroundMasker) and the same precursor flow; frames are scored once our
// filter has finished learning its PDFs.
//
// Scored pixels: the true visitor pixels (truly foreground with a true depth), inside the mask or
// not. A method's output there is a depth (error e = d - d_true, in cm) or a hole. The hole rule:
// a hole scores the raw sensor's average over the true visitor pixels of the same frames, in the
// metric at hand: E^2, the sensor's mean squared error, in the depth error; S, the sensor's mean
// (e_i - e_{i-1})^2 over the pixels it read in both frames, for a pixel pair with a hole in
// either frame. So the sensor's own holes cost what its readings cost on average, a hole is never
// free, a filter gains from a hole only where its own output would be worse than the sensor's
// average, and no constant is tuned (docs/depthfilter.md, "Holes in the metrics").
// Metrics per method, pooled over one or more camera streams:
//   temporal_mse_cm2  the paper's MSE' (Equation 2) of the depth error: mean over consecutive
//                     frame pairs of the mean over the pixels that are true visitor pixels in both
//                     frames of (e_i - e_{i-1})^2, or S where there is a hole. NaN when no pixel
//                     pair was scored (never 0 for "nothing to score");
//   depth_rmse_cm     RMS error over every scored pixel, a hole counting E^2 (a filter that
//                     freezes or smears depth loses here); NaN without scored pixels;
//   coverage          share of the true visitor pixels that get an output depth;
//   hole_pair_ratio   share of the temporal metric's pixel pairs with a hole in either frame;
//   raw_holes_filled  of the true visitor pixels the sensor gave no depth, the share that gets
//                     one (raw: 0);
//   ghost_ratio       share of output pixels where the truth has no visitor (trails), not
//                     counted in the metrics above;
//   depth_change_cm2  the literal frame-to-frame change (d_i - d_{i-1})^2 over the pairs with an
//                     output in both frames: real motion included, holes not counted. A
//                     diagnostic, compared with the truth's own value;
//   sensor_rmse_cm, sensor_temporal_mse_cm2  E and S, the same for every method on the same frames;
//   ms_per_frame      wall time of the method's depth filtering alone, per frame.
// Every ratio without anything to count is NaN.
#pragma once

#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "holo/core/rgbd_frame.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/mask_persistence.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/surface_witness.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/eval/coverage_breakdown.hpp"
#include "holo/eval/depth_baselines.hpp"

namespace holo::eval {

// Adversary: ours' output with every pixel dropped whose depth changed by more than
// DepthEvaluationConfig::adversary_max_change_m since ours' previous frame (HoleLeavingAdversary).
enum class DepthMethod { Ours = 0, Raw, Median, Taa, Adversary };
inline constexpr std::array<DepthMethod, 5> kDepthMethods{
    DepthMethod::Ours, DepthMethod::Raw, DepthMethod::Median, DepthMethod::Taa, DepthMethod::Adversary};
const char* depthMethodName(DepthMethod method);  // "ours", "raw", "median", "taa", "adversary"

struct GroundTruthFrame {
  RgbdFrame frame;          // as the sensor delivers it
  cv::Mat true_depth;       // CV_32FC1 metres
  cv::Mat true_foreground;  // CV_8UC1, non-zero = truly foreground
};

struct DepthMethodMetrics {
  double temporal_mse_cm2 = 0.0;
  double depth_rmse_cm = 0.0;
  double coverage = 0.0;
  double hole_pair_ratio = 0.0;
  double raw_holes_filled = 0.0;
  double ghost_ratio = 0.0;
  double depth_change_cm2 = 0.0;
  double sensor_rmse_cm = 0.0;
  double sensor_temporal_mse_cm2 = 0.0;
  double ms_per_frame = 0.0;
  long scored_frames = 0;
};

// A Markdown table of the metrics, one row per (name, metrics); NaN prints as "n/a".
std::string depthMetricsTable(std::span<const std::pair<std::string, DepthMethodMetrics>> rows);

// Keeps a pixel of its input only where the input's depth changed by at most `max_change_m`
// since the previous input (or had none there): the filter that wins the temporal metric by
// leaving holes where the depth moves. For testing the metrics only. Input and output CV_32FC1
// metres, 0 = hole.
class HoleLeavingAdversary {
 public:
  explicit HoleLeavingAdversary(float max_change_m);
  cv::Mat apply(const cv::Mat& depth);

 private:
  float max_change_m_;
  cv::Mat previous_;
};

// Accumulates the metrics above for one method on one camera stream, frame by frame. Usable on
// its own to score any filter (tests score frozen and over-smoothed filters with it).
class DepthScorer {
 public:
  // output: CV_32FC1 metres (0 = hole); truth: the frame as the sensor delivered it (its depth sets
  // what holes cost), its true depth and true foreground, all of one size. `seconds` is the
  // method's time on this frame. Consecutive calls are consecutive frames.
  void add(const cv::Mat& output, const GroundTruthFrame& truth, double seconds = 0.0);
  DepthMethodMetrics metrics() const;
  // Pools the sums of several streams (not an average of averages).
  void merge(const DepthScorer& other);

 private:
  // One pair of consecutive frames. Kept per pair because S, which its holes cost, is known only
  // once every frame has been added.
  struct FramePair {
    double error_change_sum = 0.0;  // (e_i - e_{i-1})^2 over the pixel pairs with an output in both
    double depth_change_sum = 0.0;  // (d_i - d_{i-1})^2 over the same pairs
    long output_pairs = 0, hole_pairs = 0;
  };
  std::vector<FramePair> pairs_;
  double error_sq_sum_ = 0.0;  // e^2 over the true visitor pixels with an output
  long visitor_pixels_ = 0, covered_ = 0;
  long raw_holes_ = 0, raw_holes_filled_ = 0;  // true visitor pixels without a reading
  double sensor_error_sq_sum_ = 0.0;           // the sensor's e^2 over the true visitor pixels it read
  long sensor_measured_ = 0;
  double sensor_pair_sum_ = 0.0;  // the sensor's (e_i - e_{i-1})^2 over the pairs it read in both frames
  long sensor_pairs_ = 0;
  long ghosts_ = 0, outputs_ = 0;
  double seconds_ = 0.0;
  long frames_ = 0;
  cv::Mat previous_raw_;
  cv::Mat previous_output_, previous_true_depth_, previous_true_foreground_;
};

struct DepthEvaluationConfig {
  depthfilter::ForegroundMaskConfig mask;
  depthfilter::PrecursorFlowConfig flow;
  depthfilter::MaskPersistenceConfig persistence;
  depthfilter::TemporalDepthFilterConfig filter;
  int median_window = 5;
  float taa_blend = 0.1f;
  float adversary_max_change_m = 0.03f;
  // Ours again with other settings on the same mask and flow (each stage's contribution: l_max 1
  // is ours without the pull-push), scored like the methods; none by default.
  std::vector<depthfilter::TemporalDepthFilterConfig> ours_variants;
  // Every method runs on the frames reduced by this (depthfilter/foreground_scale.hpp) and its
  // output is repeated over each reduced pixel's block before it is scored against the truth at
  // the camera's resolution: a reduced foreground pays for every true visitor pixel it misses.
  int foreground_scale = depthfilter::kDefaultForegroundScale;
  // With a foreground_scale above 1, ours' output at the camera's resolution is its reduced
  // interior with the outline decided by the camera's own readings (depthfilter/full_size_outline.hpp)
  // instead of each reduced pixel repeated over its block.
  bool full_size_outline = false;
};

// One camera stream. Not thread-safe; use one per camera.
class DepthFilterEvaluation {
 public:
  explicit DepthFilterEvaluation(DepthEvaluationConfig config = {});

  void learnBackground(const RgbdFrame& background);
  // Runs every method on the frame and scores it once our filter has stopped learning:
  // prepareFrame, then scoreFrame with the sensor's depth.
  void addFrame(const GroundTruthFrame& frame);
  // The two halves of addFrame, for the cameras to help each other in between: the mask (with
  // its persistence) and the flow of the frame; then every method on it, ours filtering
  // `ours_depth` (the sensor's depth with other cameras' fills, depthfilter::CrossCameraFill)
  // where the others see the sensor's. The mask they all use is lastMask() as it stands then.
  // ours_depth and crossCameraView are at the foreground's resolution (the frame's divided by
  // DepthEvaluationConfig::foreground_scale); the truth, lastMask() and lastOutput() at the frame's.
  void prepareFrame(const RgbdFrame& frame);
  // `witness` (the other cameras, depthfilter::OtherCameraWitness) is given to ours and its
  // variants; nullptr: none.
  void scoreFrame(const GroundTruthFrame& frame, const cv::Mat& ours_depth,
                  const depthfilter::SurfaceWitness* witness = nullptr);
  // This camera's frame for depthfilter::CrossCameraFill after prepareFrame: its mask is
  // lastMask() itself (grown in place), its background the masker's learned depth.
  depthfilter::CrossCameraView crossCameraView(const RgbdFrame& frame);

  DepthMethodMetrics metrics(DepthMethod method) const;
  // Metrics over several camera streams (sums pooled, not averages of averages).
  static DepthMethodMetrics combined(std::span<const DepthFilterEvaluation> streams, DepthMethod method);
  // The same for DepthEvaluationConfig::ours_variants[variant].
  DepthMethodMetrics variantMetrics(std::size_t variant) const;
  static DepthMethodMetrics combinedVariant(std::span<const DepthFilterEvaluation> streams,
                                            std::size_t variant);

  const cv::Mat& lastOutput(DepthMethod method) const { return methods_[std::size_t(method)].last_output; }
  const cv::Mat& lastMask() const { return last_mask_; }
  bool learning() const { return ours_.learning(); }
  // The truth itself as a method's output on every true visitor pixel: temporal MSE' 0, coverage
  // 1, and its depth_change_cm2 (the visitors' real motion) is the floor of that figure for any
  // filter that does not freeze.
  DepthMethodMetrics truthMetrics() const { return truth_.scorer.metrics(); }
  static DepthMethodMetrics combinedTruth(std::span<const DepthFilterEvaluation> streams);
  // Where ours' coverage goes over the scored frames (empty unless the filter's config records
  // its hole reasons, TemporalDepthFilterConfig::record_hole_reasons).
  const CoverageBreakdown& coverageBreakdown() const { return breakdown_; }
  static CoverageBreakdown combinedCoverageBreakdown(std::span<const DepthFilterEvaluation> streams);

 private:
  struct MethodState {
    DepthScorer scorer;
    cv::Mat last_output;
  };

  depthfilter::ForegroundMasker masker_;
  depthfilter::PrecursorFlow flow_;
  depthfilter::MaskPersistence persistence_;
  depthfilter::TemporalDepthFilter ours_;
  TemporalMedianDepthFilter median_;
  TaaDepthFilter taa_;
  HoleLeavingAdversary adversary_;
  std::vector<depthfilter::TemporalDepthFilter> variants_;
  std::vector<DepthScorer> variant_scorers_;
  int scale_ = 1;
  bool full_size_outline_ = false;
  cv::Mat previous_colour_;
  RgbdFrame reduced_;         // the frame prepareFrame got, at the foreground's resolution
  cv::Mat mask_, last_flow_;  // at the foreground's resolution
  cv::Mat last_mask_;         // mask_ at the frame's resolution
  std::array<MethodState, kDepthMethods.size()> methods_;
  MethodState truth_;
  CoverageBreakdown breakdown_;
};

}  // namespace holo::eval
