// The temporal depth filter against its baselines on a simulated scene (`holopyramid eval depth`,
// paper Table 2): every camera of the scene's museum through DepthFilterEvaluation, first the
// empty hall's background frames, then the learning frames, then the scored ones; the metrics
// pooled over the cameras (between each frame's masks and the filters the cameras fill each
// other's holes, depthfilter::CrossCameraFill), the bars' verdicts (acceptance_bars.hpp) for ours and for the
// hole-leaving adversary, and the report as JSON (NaN written as null). Next to the depth metrics,
// what a visitor sees of them: every method's output, the truth's and no visitors at all fed
// through the live reflection renderer (displayed_reflection.hpp) with the scene's relic, the
// displayed reflection flicker of each (reflection_flicker.hpp) and its bars.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/eval/depth_evaluation.hpp"
#include "holo/eval/reflection_flicker.hpp"

namespace holo::eval {

struct SimulatedDepthOptions {
  std::string scene = "museum";  // built-in scene name or scene YAML file
  std::string visitor_model;     // empty: the scene's own
  int frames = 60;               // scored frames, after the learning frames (>= 1)
  int width = 0, height = 0;     // camera size; 0: the scene's
  int learning_frames = depthfilter::TemporalDepthFilterConfig{}.learning_frames;
  int levels = depthfilter::TemporalDepthFilterConfig{}.levels;  // ours' l_max
  // Ours again with each of these l_max on the same masks and flow: what each pyramid level
  // adds (l_max 1: no pull-push). Reported as the methods "ours l_max=N".
  std::vector<int> compared_levels = {1, 2};
  bool figure = false;  // also draw SimulatedDepthEvaluation::figure
  // The mask's persistence where the sensor reads nothing (false: its contribution).
  bool mask_persistence = depthfilter::MaskPersistenceConfig{}.enabled;
  // The cameras filling each other's holes before ours filters (depthfilter::CrossCameraFill;
  // false: each camera on its own).
  bool cross_camera = depthfilter::CrossCameraFillConfig{}.enabled;
  // The precursor flow's forward-backward check (depthfilter::PrecursorFlowConfig::round_trip_check),
  // for every method (they share the flow).
  bool round_trip_check = depthfilter::PrecursorFlowConfig{}.round_trip_check;
  // Each scored frame of every method rendered by the live renderer and its displayed reflection
  // flicker scored (false: the depth metrics alone).
  bool reflection_flicker = true;
  int view_size = 0;  // of the face views the flicker is measured on; 0: the live loop's
  // The mask's opening keeps the thin limbs joined to a body (false: its contribution).
  bool keep_attached_limbs = depthfilter::ForegroundMaskConfig{}.keep_attached_limbs;
  // Every method on the frames reduced by this, scored at the camera's resolution
  // (DepthEvaluationConfig::foreground_scale).
  int foreground_scale = depthfilter::kDefaultForegroundScale;
  // Ours' outline at the camera's resolution with a reduced foreground
  // (DepthEvaluationConfig::full_size_outline).
  bool full_size_outline = false;
  // Ours' hole fills at the mask's edge and on a trusted precursor's surface (false: each one's
  // contribution; depthfilter::TemporalDepthFilterConfig).
  bool fill_mask_edge = depthfilter::TemporalDepthFilterConfig{}.fill_mask_edge;
  bool fill_on_precursor_surface = depthfilter::TemporalDepthFilterConfig{}.fill_on_precursor_surface;
  // The mask's growth into readings of unknown background depth, in pixels (0: its contribution;
  // depthfilter::ForegroundMaskConfig::unknown_background_growth_steps).
  int mask_growth_steps = depthfilter::ForegroundMaskConfig{}.unknown_background_growth_steps;
  // Ours' holes between two surfaces of their colour decided by the other cameras' depth
  // (false: its contribution; depthfilter::TemporalDepthFilterConfig::fill_witnessed).
  bool fill_witnessed = depthfilter::TemporalDepthFilterConfig{}.fill_witnessed;
};

struct SimulatedDepthEvaluation {
  // scene, frames, learning_frames, levels, mask_persistence, keep_attached_limbs, mask_growth_steps,
  // foreground_scale,
  // cross_camera (and the cross-camera step's filled and confirmed pixels per camera frame), cameras, width,
  // height, methods (each method's metrics, the compared l_max among them), bars (the verdicts for ours and
  // the adversary), truth_depth_change_cm2, coverage_breakdown (CoverageBreakdown::toJson).
  nlohmann::json report;
  // Each method's pooled metrics, in kDepthMethods' order, then the compared l_max (for
  // depthMetricsTable).
  std::vector<std::pair<std::string, DepthMethodMetrics>> rows;
  // Where ours' coverage goes (CoverageBreakdown::table; the same in report["coverage_breakdown"]).
  std::string coverage_table;
  // With SimulatedDepthOptions::figure, a Fig. 9-like picture (BGR) of the last frame of the
  // camera that sees the most visitor pixels: its colour frame, then raw's, the median's, TAA's,
  // ours' and the truth's point clouds seen 0.8 m behind and 0.2 m to the right of the camera.
  cv::Mat figure;
  // With SimulatedDepthOptions::reflection_flicker: the displayed reflection flicker of ours, raw,
  // the median, TAA, the adversary and "nobody" (the renderer fed no visitors: the reflection
  // left out altogether), and the truth's (its displayed_change is the visitors' own change).
  std::vector<std::pair<std::string, ReflectionFlickerMetrics>> flicker_rows;
  // Their flicker per frame pair, ours, raw, the median and TAA, as a picture (BGR, log scale).
  cv::Mat flicker_figure;
};

SimulatedDepthEvaluation evaluateSimulatedDepth(const SimulatedDepthOptions& options);

}  // namespace holo::eval
