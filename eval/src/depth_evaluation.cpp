#include "holo/eval/depth_evaluation.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/depthfilter/full_size_outline.hpp"
#include "table_number.hpp"

namespace holo::eval {

const char* depthMethodName(DepthMethod method) {
  switch (method) {
    case DepthMethod::Ours:
      return "ours";
    case DepthMethod::Raw:
      return "raw";
    case DepthMethod::Median:
      return "median";
    case DepthMethod::Taa:
      return "taa";
    case DepthMethod::Adversary:
      return "adversary";
  }
  return "?";
}

DepthFilterEvaluation::DepthFilterEvaluation(DepthEvaluationConfig config)
    : masker_(config.mask),
      flow_(config.flow),
      persistence_(config.persistence),
      ours_(config.filter),
      median_(config.median_window),
      taa_(config.taa_blend),
      adversary_(config.adversary_max_change_m),
      variant_scorers_(config.ours_variants.size()),
      scale_(config.foreground_scale),
      full_size_outline_(config.full_size_outline),
      breakdown_(config.mask) {
  depthfilter::checkForegroundScale(scale_, 0, 0);  // its range; each frame's size in prepareFrame
  for (const depthfilter::TemporalDepthFilterConfig& variant : config.ours_variants)
    variants_.emplace_back(variant);
}

void DepthFilterEvaluation::learnBackground(const RgbdFrame& background) {
  masker_.learnBackground(depthfilter::reducedFrame(background, scale_));
}

void DepthScorer::add(const cv::Mat& out, const GroundTruthFrame& truth, double seconds) {
  const cv::Size size = truth.true_depth.size();
  if (out.type() != CV_32FC1 || out.size() != size || truth.true_depth.type() != CV_32FC1 ||
      truth.true_foreground.type() != CV_8UC1 || truth.true_foreground.size() != size ||
      truth.frame.depth.type() != CV_32FC1 || truth.frame.depth.size() != size)
    throw Error(
        "DepthScorer: expected a CV_32FC1 output, true depth and measured depth and a CV_8UC1 true "
        "foreground, "
        "all of one size");
  seconds_ += seconds;
  ++frames_;
  const bool has_previous = !previous_output_.empty() && previous_output_.size() == size;
  FramePair pair;
  for (int y = 0; y < out.rows; ++y) {
    const float* d = out.ptr<float>(y);
    const float* td = truth.true_depth.ptr<float>(y);
    const std::uint8_t* tf = truth.true_foreground.ptr<std::uint8_t>(y);
    const float* raw = truth.frame.depth.ptr<float>(y);
    const float* prev = has_previous ? previous_output_.ptr<float>(y) : nullptr;
    const float* prev_raw = has_previous ? previous_raw_.ptr<float>(y) : nullptr;
    const float* prev_td = has_previous ? previous_true_depth_.ptr<float>(y) : nullptr;
    const std::uint8_t* prev_tf = has_previous ? previous_true_foreground_.ptr<std::uint8_t>(y) : nullptr;
    for (int x = 0; x < out.cols; ++x) {
      const bool has = d[x] > 0.0f;
      outputs_ += has;
      if (!(tf[x] && td[x] > 0.0f)) {
        ghosts_ += has;
        continue;
      }
      ++visitor_pixels_;
      covered_ += has;
      const bool sensed = std::isfinite(raw[x]) && raw[x] > 0.0f;
      const double sensor_e = 100.0 * (double(raw[x]) - td[x]);
      if (sensed) {
        sensor_error_sq_sum_ += sensor_e * sensor_e;
        ++sensor_measured_;
      } else {
        ++raw_holes_;
        raw_holes_filled_ += has;
      }
      const double e = 100.0 * (double(d[x]) - td[x]);
      if (has) error_sq_sum_ += e * e;
      if (!prev || !(prev_tf[x] && prev_td[x] > 0.0f)) continue;
      if (sensed && std::isfinite(prev_raw[x]) && prev_raw[x] > 0.0f) {
        const double sensor_change = sensor_e - 100.0 * (double(prev_raw[x]) - prev_td[x]);
        sensor_pair_sum_ += sensor_change * sensor_change;
        ++sensor_pairs_;
      }
      if (!(has && prev[x] > 0.0f)) {
        ++pair.hole_pairs;
        continue;
      }
      const double error_change = e - 100.0 * (double(prev[x]) - prev_td[x]);
      const double change = 100.0 * (double(d[x]) - prev[x]);
      pair.error_change_sum += error_change * error_change;
      pair.depth_change_sum += change * change;
      ++pair.output_pairs;
    }
  }
  if (has_previous) pairs_.push_back(pair);
  previous_output_ = out.clone();
  previous_raw_ = truth.frame.depth.clone();
  previous_true_depth_ = truth.true_depth.clone();
  previous_true_foreground_ = truth.true_foreground.clone();
}

DepthMethodMetrics DepthScorer::metrics() const {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const auto ratio = [](double num, long den) { return den > 0 ? num / double(den) : kNaN; };
  // What a hole costs. NaN when the sensor read nothing; it then poisons only figures with holes.
  const double hole_sq = ratio(sensor_error_sq_sum_, sensor_measured_);
  const double hole_pair = ratio(sensor_pair_sum_, sensor_pairs_);
  DepthMethodMetrics m;
  double temporal_sum = 0.0, change_sum = 0.0;
  long temporal_frames = 0, change_frames = 0, hole_pairs = 0, all_pairs = 0;
  for (const FramePair& p : pairs_) {
    const long n = p.output_pairs + p.hole_pairs;
    if (n == 0) continue;
    temporal_sum +=
        (p.error_change_sum + (p.hole_pairs > 0 ? double(p.hole_pairs) * hole_pair : 0.0)) / double(n);
    ++temporal_frames;
    hole_pairs += p.hole_pairs;
    all_pairs += n;
    if (p.output_pairs > 0) {
      change_sum += p.depth_change_sum / double(p.output_pairs);
      ++change_frames;
    }
  }
  m.temporal_mse_cm2 = ratio(temporal_sum, temporal_frames);
  m.hole_pair_ratio = ratio(double(hole_pairs), all_pairs);
  m.depth_change_cm2 = ratio(change_sum, change_frames);
  const long holes = visitor_pixels_ - covered_;
  m.depth_rmse_cm =
      std::sqrt(ratio(error_sq_sum_ + (holes > 0 ? double(holes) * hole_sq : 0.0), visitor_pixels_));
  m.coverage = ratio(double(covered_), visitor_pixels_);
  m.raw_holes_filled = ratio(double(raw_holes_filled_), raw_holes_);
  m.ghost_ratio = ratio(double(ghosts_), outputs_);
  m.sensor_rmse_cm = std::sqrt(hole_sq);
  m.sensor_temporal_mse_cm2 = hole_pair;
  m.ms_per_frame = ratio(1000.0 * seconds_, frames_);
  m.scored_frames = frames_;
  return m;
}

void DepthScorer::merge(const DepthScorer& o) {
  pairs_.insert(pairs_.end(), o.pairs_.begin(), o.pairs_.end());
  error_sq_sum_ += o.error_sq_sum_;
  sensor_pair_sum_ += o.sensor_pair_sum_;
  sensor_pairs_ += o.sensor_pairs_;
  visitor_pixels_ += o.visitor_pixels_;
  covered_ += o.covered_;
  raw_holes_ += o.raw_holes_;
  raw_holes_filled_ += o.raw_holes_filled_;
  sensor_error_sq_sum_ += o.sensor_error_sq_sum_;
  sensor_measured_ += o.sensor_measured_;
  ghosts_ += o.ghosts_;
  outputs_ += o.outputs_;
  seconds_ += o.seconds_;
  frames_ += o.frames_;
}

std::string depthMetricsTable(std::span<const std::pair<std::string, DepthMethodMetrics>> rows) {
  std::string table =
      "| method | temporal MSE' (cm^2) | depth RMSE (cm) | coverage | hole pairs | raw holes filled | ghosts "
      "| "
      "depth change (cm^2) | ms/frame |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [name, m] : rows)
    table += "| " + name + " | " + tableNumber(m.temporal_mse_cm2, "%.2f") + " | " +
             tableNumber(m.depth_rmse_cm, "%.2f") + " | " + tableNumber(m.coverage, "%.3f") + " | " +
             tableNumber(m.hole_pair_ratio, "%.3f") + " | " + tableNumber(m.raw_holes_filled, "%.3f") +
             " | " + tableNumber(m.ghost_ratio, "%.4f") + " | " + tableNumber(m.depth_change_cm2, "%.1f") +
             " | " + tableNumber(m.ms_per_frame, "%.1f") + " |\n";
  return table;
}

HoleLeavingAdversary::HoleLeavingAdversary(float max_change_m) : max_change_m_(max_change_m) {
  if (!(max_change_m >= 0.0f)) throw Error("HoleLeavingAdversary: max_change_m must be >= 0");
}

cv::Mat HoleLeavingAdversary::apply(const cv::Mat& depth) {
  if (depth.type() != CV_32FC1) throw Error("HoleLeavingAdversary: expected CV_32FC1 depth");
  cv::Mat out = depth.clone();
  if (previous_.size() == depth.size())
    out.forEach<float>([&](float& d, const int* p) {
      const float before = previous_.at<float>(p[0], p[1]);
      if (d > 0.0f && before > 0.0f && std::abs(d - before) > max_change_m_) d = 0.0f;
    });
  previous_ = depth.clone();
  return out;
}

void DepthFilterEvaluation::addFrame(const GroundTruthFrame& truth) {
  prepareFrame(truth.frame);
  scoreFrame(truth, reduced_.depth);
}

void DepthFilterEvaluation::prepareFrame(const RgbdFrame& frame) {
  depthfilter::checkForegroundScale(scale_, frame.colour.cols, frame.colour.rows);
  reduced_ = depthfilter::reducedFrame(frame, scale_);
  mask_ = masker_.apply(reduced_);
  last_flow_ = flow_.compute(reduced_.colour, previous_colour_);
  persistence_.extend(mask_, reduced_, last_flow_);
  previous_colour_ = reduced_.colour.clone();
  last_mask_ = depthfilter::expandedToFull(mask_, frame.colour.size());
}

depthfilter::CrossCameraView DepthFilterEvaluation::crossCameraView(const RgbdFrame& frame) {
  if (frame.colour.size() != reduced_.colour.size() * scale_)
    throw Error("DepthFilterEvaluation: crossCameraView needs prepareFrame on the same frame first");
  return {reduced_.depth, mask_, masker_.backgroundDepth()};
}

void DepthFilterEvaluation::scoreFrame(const GroundTruthFrame& truth, const cv::Mat& ours_depth,
                                       const depthfilter::SurfaceWitness* witness) {
  const RgbdFrame& frame = truth.frame;
  if (truth.true_depth.type() != CV_32FC1 || truth.true_depth.size() != frame.depth.size() ||
      truth.true_foreground.type() != CV_8UC1 || truth.true_foreground.size() != frame.depth.size() ||
      ours_depth.type() != CV_32FC1 || ours_depth.size() != reduced_.depth.size())
    throw Error(
        "DepthFilterEvaluation: expected true depth CV_32FC1 and true foreground CV_8UC1 of the frame's "
        "size, our depth CV_32FC1 of the foreground's");
  if (mask_.size() * scale_ != frame.depth.size())
    throw Error("DepthFilterEvaluation: scoreFrame needs prepareFrame on the same frame first");
  // The cameras' fill may have grown the mask since prepareFrame.
  last_mask_ = depthfilter::expandedToFull(mask_, frame.depth.size());
  const depthfilter::DepthFilterInput input{reduced_.colour, reduced_.depth, mask_, last_flow_};
  const depthfilter::DepthFilterInput ours_input{reduced_.colour, ours_depth, mask_, last_flow_, witness};
  const auto at_frame_size = [&](const cv::Mat& reduced) {
    return depthfilter::expandedToFull(reduced, frame.depth.size());
  };
  const bool score = !ours_.learning();  // decided before this frame, like the filter itself

  for (DepthMethod method : kDepthMethods) {
    MethodState& state = methods_[std::size_t(method)];
    const auto start = std::chrono::steady_clock::now();
    cv::Mat out;
    switch (method) {
      case DepthMethod::Ours:
        out = ours_.apply(ours_input);
        break;
      case DepthMethod::Raw:
        out = cv::Mat::zeros(reduced_.depth.size(), CV_32FC1);
        reduced_.depth.copyTo(out, mask_);
        out.forEach<float>([](float& d, const int*) {
          if (!std::isfinite(d) || d < 0.0f) d = 0.0f;
        });
        break;
      case DepthMethod::Median:
        out = median_.apply(input);
        break;
      case DepthMethod::Taa:
        out = taa_.apply(input);
        break;
      case DepthMethod::Adversary:
        // Runs after ours in kDepthMethods; its time is the dropping alone.
        out = adversary_.apply(methods_[std::size_t(DepthMethod::Ours)].last_output);
        break;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (method == DepthMethod::Ours && full_size_outline_ && scale_ > 1)
      out = depthfilter::fullSizeOutline(mask_, out, masker_.backgroundDepth(), frame.depth, scale_,
                                         {masker_.config().depth_margin_m, masker_.config().depth_margin_z2})
                .depth;
    else if (method != DepthMethod::Adversary)
      out = at_frame_size(out);  // the adversary's input already is
    if (score) state.scorer.add(out, truth, seconds);
    state.last_output = out;
  }
  for (std::size_t v = 0; v < variants_.size(); ++v) {
    const auto start = std::chrono::steady_clock::now();
    const cv::Mat reduced_out = variants_[v].apply(ours_input);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const cv::Mat out = at_frame_size(reduced_out);
    if (score) variant_scorers_[v].add(out, truth, seconds);
  }
  if (score && !ours_.holeReasons().empty())
    breakdown_.add({truth.true_foreground, truth.true_depth, frame.depth,
                    at_frame_size(masker_.backgroundDepth()), last_mask_,
                    methods_[std::size_t(DepthMethod::Ours)].last_output,
                    at_frame_size(ours_.holeReasons())});
  if (score) {
    cv::Mat true_output = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
    truth.true_depth.copyTo(true_output, truth.true_foreground);
    truth_.scorer.add(true_output, truth);
    truth_.last_output = true_output;
  }
}

DepthMethodMetrics DepthFilterEvaluation::metrics(DepthMethod method) const {
  return methods_[std::size_t(method)].scorer.metrics();
}

DepthMethodMetrics DepthFilterEvaluation::combined(std::span<const DepthFilterEvaluation> streams,
                                                   DepthMethod method) {
  DepthScorer total;
  for (const DepthFilterEvaluation& e : streams) total.merge(e.methods_[std::size_t(method)].scorer);
  // Frames are counted per stream; time per frame is per camera frame.
  return total.metrics();
}

DepthMethodMetrics DepthFilterEvaluation::variantMetrics(std::size_t variant) const {
  return variant_scorers_.at(variant).metrics();
}

DepthMethodMetrics DepthFilterEvaluation::combinedVariant(std::span<const DepthFilterEvaluation> streams,
                                                          std::size_t variant) {
  DepthScorer total;
  for (const DepthFilterEvaluation& e : streams) total.merge(e.variant_scorers_.at(variant));
  return total.metrics();
}

DepthMethodMetrics DepthFilterEvaluation::combinedTruth(std::span<const DepthFilterEvaluation> streams) {
  DepthScorer total;
  for (const DepthFilterEvaluation& e : streams) total.merge(e.truth_.scorer);
  return total.metrics();
}

CoverageBreakdown DepthFilterEvaluation::combinedCoverageBreakdown(
    std::span<const DepthFilterEvaluation> streams) {
  CoverageBreakdown total(depthfilter::ForegroundMaskConfig{});
  for (const DepthFilterEvaluation& e : streams) total.merge(e.breakdown_);
  return total;
}

}  // namespace holo::eval
