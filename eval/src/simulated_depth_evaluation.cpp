#include "holo/eval/simulated_depth_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "figure_label.hpp"
#include "holo/core/progress.hpp"
#include "holo/depthfilter/cloud_view.hpp"
#include "holo/depthfilter/other_camera_witness.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/displayed_reflection.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/museum_installation.hpp"

namespace holo::eval {
namespace {

// NaN (nothing to score) is written as null.
nlohmann::json toJson(const DepthMethodMetrics& m) {
  return {{"temporal_mse_cm2", m.temporal_mse_cm2},
          {"depth_rmse_cm", m.depth_rmse_cm},
          {"coverage", m.coverage},
          {"hole_pair_ratio", m.hole_pair_ratio},
          {"raw_holes_filled", m.raw_holes_filled},
          {"ghost_ratio", m.ghost_ratio},
          {"depth_change_cm2", m.depth_change_cm2},
          {"sensor_rmse_cm", m.sensor_rmse_cm},
          {"sensor_temporal_mse_cm2", m.sensor_temporal_mse_cm2},
          {"ms_per_frame", m.ms_per_frame},
          {"scored_frames", m.scored_frames}};
}

nlohmann::json toJson(const DepthBarVerdicts& v) {
  return {{"below_median", v.below_median}, {"below_taa", v.below_taa}, {"rmse_below_raw", v.rmse_below_raw},
          {"coverage", v.coverage},         {"ghosts", v.ghosts},       {"all", v.all()}};
}

// Colour frame, then each method's cloud and the truth, seen 0.8 m behind and 0.2 m to the right
// of the camera (the paper's Fig. 9 viewpoint).
cv::Mat depthMethodsFigure(const sim::Museum& museum, int camera, const sim::SimulatedFrame& frame,
                           const DepthFilterEvaluation& evaluation) {
  const Intrinsics& K = museum.camera(camera).intrinsics();
  const vec3 shift(0.2f, 0.0f, -0.8f);
  double far = 0.0;
  cv::minMaxLoc(frame.true_depth, nullptr, &far, nullptr, nullptr, evaluation.lastMask());
  const float far_m = std::max(1.0f, float(far));
  std::vector<cv::Mat> panels{labelled(frame.frame.colour.clone(), "camera " + std::to_string(camera))};
  for (DepthMethod m : {DepthMethod::Raw, DepthMethod::Median, DepthMethod::Taa, DepthMethod::Ours})
    panels.push_back(
        labelled(depthfilter::renderShiftedCloud(evaluation.lastOutput(m), K, shift, 0.3f, far_m),
                 depthMethodName(m)));
  cv::Mat truth = cv::Mat::zeros(frame.true_depth.size(), CV_32FC1);
  frame.true_depth.copyTo(truth, frame.foreground);
  panels.push_back(labelled(depthfilter::renderShiftedCloud(truth, K, shift, 0.3f, far_m), "truth"));
  cv::Mat row;
  cv::hconcat(panels, row);
  return row;
}

nlohmann::json toJson(const ReflectionFlickerMetrics& m) {
  return {{"flicker_levels2", m.flicker},
          {"temporal_levels2", m.temporal},
          {"missing_levels2", m.missing},
          {"missing_share", m.missing_share},
          {"displayed_change_levels2", m.displayed_change},
          {"scored_pairs", m.scored_pairs}};
}

// The relic as the live loop shows it, rendered for the truth, each depth method and nobody.
class FlickerRun {
 public:
  // The rendered methods: the truth first, then kDepthMethods, then nobody, then two diagnostics of
  // where ours' flicker comes from: the true depth on the shared mask, whatever the pixel sees
  // (what a perfect depth filter would show: the mask's share), and the true depth on ours' pixels
  // only (ours' holes without its errors: the rest is its depth's).
  static constexpr std::size_t kTruth = 0, kNobody = kDepthMethods.size() + 1, kTruthOnMask = kNobody + 1,
                               kTruthOnOurs = kTruthOnMask + 1;

  FlickerRun(const sim::Museum& museum, int view_size)
      : scene_(museum.relic(), {}),
        ibl_(reflect::Environment(museum.renderPanorama(panoramaWidth(), panoramaWidth() / 2), 0.0f,
                                  simulated::museumPanoramaProxy(museum))) {
    std::vector<CameraModel> cameras;
    for (int c = 0; c < museum.cameraCount(); ++c) cameras.push_back(museum.camera(c));
    const std::vector<CameraModel> views = defaultFaceViews(scene_, view_size);
    for (std::size_t m = 0; m <= kTruthOnOurs; ++m)
      renderers_.push_back(std::make_unique<DisplayedReflection>(
          scene_, ibl_, cameras, museum.description().camera.exposure, views));
    scorers_.resize(renderers_.size());
  }

  // One frame: frames[m][c] is method m's frame of camera c (in the order above).
  void add(const std::vector<std::vector<MethodCameraFrame>>& frames) {
    if (!exposure_fixed_) {
      // As the live loop does: the first frame's automatic choice, then fixed for every method.
      renderers_[kTruth]->render(frames[kTruth]);
      for (auto& r : renderers_) r->setExposure(renderers_[kTruth]->lastExposure());
      exposure_fixed_ = true;
    }
    const DisplayedFrame truth = renderers_[kTruth]->render(frames[kTruth]);
    scorers_[kTruth].add(truth, truth);
    for (std::size_t m = 1; m < renderers_.size(); ++m)
      scorers_[m].add(renderers_[m]->render(frames[m]), truth);
  }

  ReflectionFlickerMetrics metrics(std::size_t method) const { return scorers_[method].metrics(); }

 private:
  // The live loop's simulated hall panorama.
  static int panoramaWidth() { return pipeline::FrameLoopOptions{}.panorama_width; }
  reflect::RenderScene scene_;
  reflect::PrefilteredIbl ibl_;
  std::vector<std::unique_ptr<DisplayedReflection>> renderers_;
  std::vector<ReflectionFlickerScorer> scorers_;
  bool exposure_fixed_ = false;
};

// Flicker per frame pair of each series on a log axis, with a legend.
cv::Mat flickerFigure(const std::vector<std::pair<std::string, ReflectionFlickerMetrics>>& series,
                      const std::string& title) {
  const std::vector<cv::Scalar> colours = {{40, 160, 40}, {110, 110, 110}, {200, 120, 30}, {30, 120, 230}};
  const int width = 760, height = 400, left = 70, right = 150, top = 36, bottom = 44;
  cv::Mat figure(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  double lo = 1e300, hi = 0.0;
  std::size_t pairs = 0;
  for (const auto& [name, m] : series) {
    pairs = std::max(pairs, m.per_pair.size());
    for (double v : m.per_pair)
      if (v > 0.0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  if (pairs < 2 || !(hi > 0.0)) return figure;
  const double y0 = std::floor(std::log10(lo)), y1 = std::ceil(std::log10(hi)) + (hi == lo ? 1.0 : 0.0);
  const int plot_w = width - left - right, plot_h = height - top - bottom;
  const auto px = [&](std::size_t i) { return left + int(double(i) / double(pairs - 1) * plot_w); };
  const auto py = [&](double v) { return top + int((y1 - std::log10(v)) / (y1 - y0) * plot_h); };
  const cv::Scalar ink(0, 0, 0), grid(225, 225, 225);
  for (double d = y0; d <= y1; d += 1.0) {
    const int y = py(std::pow(10.0, d));
    cv::line(figure, {left, y}, {left + plot_w, y}, grid);
    cv::putText(figure, "1e" + std::to_string(int(d)), {8, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
                cv::LINE_AA);
  }
  for (std::size_t i = 0; i < pairs; i += 10) {
    cv::line(figure, {px(i), top + plot_h}, {px(i), top + plot_h + 5}, ink);
    cv::putText(figure, std::to_string(i + 1), {px(i) - 8, top + plot_h + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                ink, 1, cv::LINE_AA);
  }
  cv::rectangle(figure, {left, top}, {left + plot_w, top + plot_h}, ink);
  cv::putText(figure, title, {left, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.55, ink, 1, cv::LINE_AA);
  cv::putText(figure, "frame pair", {left + plot_w / 2 - 40, height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink,
              1, cv::LINE_AA);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const cv::Scalar colour = colours[s % colours.size()];
    const std::vector<double>& v = series[s].second.per_pair;
    for (std::size_t i = 1; i < v.size(); ++i)
      if (v[i - 1] > 0.0 && v[i] > 0.0 && std::isfinite(v[i - 1]) && std::isfinite(v[i]))
        cv::line(figure, {px(i - 1), py(v[i - 1])}, {px(i), py(v[i])}, colour, 2, cv::LINE_AA);
    const int y = top + 20 + int(s) * 22;
    cv::line(figure, {width - right + 12, y - 4}, {width - right + 36, y - 4}, colour, 2, cv::LINE_AA);
    cv::putText(figure, series[s].first, {width - right + 42, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
                cv::LINE_AA);
  }
  return figure;
}

}  // namespace

SimulatedDepthEvaluation evaluateSimulatedDepth(const SimulatedDepthOptions& o) {
  sim::SceneDescription description = sim::loadScene(o.scene);
  if (o.width > 0) description.camera.width = o.width;
  if (o.height > 0) description.camera.height = o.height;
  if (!o.visitor_model.empty())
    description.visitor_model = sim::visitorModelFromName(o.visitor_model, "", "--visitor-model");
  const sim::Museum museum(description);

  DepthEvaluationConfig config;
  config.filter.learning_frames = o.learning_frames;
  config.filter.levels = o.levels;
  config.persistence.enabled = o.mask_persistence;
  config.flow.round_trip_check = o.round_trip_check;
  config.mask.keep_attached_limbs = o.keep_attached_limbs;
  config.mask.unknown_background_growth_steps = o.mask_growth_steps;
  config.foreground_scale = o.foreground_scale;
  config.full_size_outline = o.full_size_outline;
  config.filter.record_hole_reasons = true;
  config.filter.fill_mask_edge = o.fill_mask_edge;
  config.filter.fill_on_precursor_surface = o.fill_on_precursor_surface;
  config.filter.fill_witnessed = o.fill_witnessed;
  for (int levels : o.compared_levels) {
    depthfilter::TemporalDepthFilterConfig variant = config.filter;
    variant.levels = levels;
    config.ours_variants.push_back(variant);
  }
  std::vector<DepthFilterEvaluation> streams;
  for (int c = 0; c < museum.cameraCount(); ++c) streams.emplace_back(config);
  constexpr int kBackgroundFrames = 8;
  const int total = o.learning_frames + o.frames;
  ProgressReporter progress(std::int64_t(museum.cameraCount()) * (kBackgroundFrames + total), "eval depth");
  for (int c = 0; c < museum.cameraCount(); ++c)
    for (int t = 0; t < kBackgroundFrames; ++t, progress.update())
      streams[std::size_t(c)].learnBackground(museum.renderCamera(c, t, false).frame);

  std::vector<CameraModel> cameras;
  for (int c = 0; c < museum.cameraCount(); ++c)
    cameras.push_back(depthfilter::reducedCamera(museum.camera(c), o.foreground_scale));
  depthfilter::CrossCameraFillConfig cross_config;
  cross_config.enabled = o.cross_camera;
  const depthfilter::CrossCameraFill cross_camera(cameras, cross_config);
  const depthfilter::OtherCameraWitnesses witnesses(cameras);
  long filled = 0, confirmed = 0, camera_frames = 0;

  int figure_camera = 0;
  long figure_pixels = -1;
  sim::SimulatedFrame figure_frame;
  std::vector<sim::SimulatedFrame> frames(std::size_t(museum.cameraCount()));
  std::vector<depthfilter::CrossCameraView> views(frames.size());
  std::vector<depthfilter::CrossCameraCounts> counts;
  std::unique_ptr<FlickerRun> flicker;
  if (o.reflection_flicker)
    flicker = std::make_unique<FlickerRun>(
        museum, o.view_size > 0 ? o.view_size : pipeline::FrameLoopOptions{}.view_size);
  std::vector<std::vector<MethodCameraFrame>> shown(FlickerRun::kTruthOnOurs + 1,
                                                    std::vector<MethodCameraFrame>(frames.size()));
  for (int t = 0; t < total; ++t) {
    for (int c = 0; c < museum.cameraCount(); ++c) {
      frames[std::size_t(c)] = museum.renderCamera(c, t);
      streams[std::size_t(c)].prepareFrame(frames[std::size_t(c)].frame);
      views[std::size_t(c)] = streams[std::size_t(c)].crossCameraView(frames[std::size_t(c)].frame);
    }
    const std::vector<cv::Mat> ours_depth = cross_camera.apply(views, &counts);
    for (int c = 0; c < museum.cameraCount(); ++c, progress.update()) {
      sim::SimulatedFrame& f = frames[std::size_t(c)];
      const bool scored = !streams[std::size_t(c)].learning();
      const depthfilter::OtherCameraWitness witness = witnesses.witnessFor(views, std::size_t(c));
      streams[std::size_t(c)].scoreFrame({f.frame, f.true_depth, f.foreground}, ours_depth[std::size_t(c)],
                                         &witness);
      if (scored) {
        filled += counts[std::size_t(c)].filled;
        confirmed += counts[std::size_t(c)].confirmed;
        ++camera_frames;
        const DepthFilterEvaluation& stream = streams[std::size_t(c)];
        cv::Mat true_depth = cv::Mat::zeros(f.true_depth.size(), CV_32FC1);
        f.true_depth.copyTo(true_depth, f.foreground);
        shown[FlickerRun::kTruth][std::size_t(c)] = {f.frame.colour, f.foreground, true_depth};
        for (DepthMethod m : kDepthMethods)
          shown[std::size_t(m) + 1][std::size_t(c)] = {f.frame.colour, stream.lastMask(),
                                                       stream.lastOutput(m)};
        shown[FlickerRun::kNobody][std::size_t(c)] = {f.frame.colour, stream.lastMask(), cv::Mat()};
        cv::Mat true_on_mask = cv::Mat::zeros(f.true_depth.size(), CV_32FC1);
        f.true_depth.copyTo(true_on_mask, stream.lastMask());
        shown[FlickerRun::kTruthOnMask][std::size_t(c)] = {f.frame.colour, stream.lastMask(), true_on_mask};
        cv::Mat true_on_ours = cv::Mat::zeros(f.true_depth.size(), CV_32FC1);
        f.true_depth.copyTo(true_on_ours, stream.lastOutput(DepthMethod::Ours) > 0.0f);
        shown[FlickerRun::kTruthOnOurs][std::size_t(c)] = {f.frame.colour, stream.lastMask(), true_on_ours};
      }
      if (t + 1 == total && cv::countNonZero(f.foreground) > figure_pixels) {
        figure_pixels = cv::countNonZero(f.foreground);
        figure_camera = c;
        figure_frame = std::move(f);
      }
    }
    if (flicker && !streams[0].learning()) flicker->add(shown);
  }
  progress.done();

  SimulatedDepthEvaluation result;
  nlohmann::json methods, bars;
  std::vector<std::pair<std::string, DepthMethodMetrics>>& rows = result.rows;
  for (DepthMethod m : kDepthMethods) {
    rows.emplace_back(depthMethodName(m), DepthFilterEvaluation::combined(streams, m));
    methods[depthMethodName(m)] = toJson(rows.back().second);
  }
  for (std::size_t v = 0; v < o.compared_levels.size(); ++v) {
    const std::string name = "ours l_max=" + std::to_string(o.compared_levels[v]);
    rows.emplace_back(name, DepthFilterEvaluation::combinedVariant(streams, v));
    methods[name] = toJson(rows.back().second);
  }
  const auto combined = [&](DepthMethod m) { return rows[std::size_t(m)].second; };
  const CoverageBreakdown breakdown = DepthFilterEvaluation::combinedCoverageBreakdown(streams);
  result.coverage_table = breakdown.table();
  for (DepthMethod m : {DepthMethod::Ours, DepthMethod::Adversary})
    bars[depthMethodName(m)] = toJson(checkDepthBars(
        combined(m), combined(DepthMethod::Raw), combined(DepthMethod::Median), combined(DepthMethod::Taa)));
  result.report = {{"scene", description.name},
                   {"frames", o.frames},
                   {"learning_frames", o.learning_frames},
                   {"levels", o.levels},
                   {"mask_persistence", o.mask_persistence},
                   {"keep_attached_limbs", o.keep_attached_limbs},
                   {"mask_growth_steps", o.mask_growth_steps},
                   {"foreground_scale", o.foreground_scale},
                   {"full_size_outline", o.full_size_outline},
                   {"cross_camera", o.cross_camera},
                   {"round_trip_check", o.round_trip_check},
                   {"cross_camera_filled_per_camera_frame",
                    camera_frames > 0 ? double(filled) / double(camera_frames) : 0.0},
                   {"cross_camera_confirmed_per_camera_frame",
                    camera_frames > 0 ? double(confirmed) / double(camera_frames) : 0.0},
                   {"cameras", museum.cameraCount()},
                   {"width", description.camera.width},
                   {"height", description.camera.height},
                   {"methods", methods},
                   {"bars", bars},
                   {"truth_depth_change_cm2", DepthFilterEvaluation::combinedTruth(streams).depth_change_cm2},
                   {"coverage_breakdown", breakdown.toJson()}};
  if (flicker) {
    nlohmann::json flicker_methods, flicker_bars;
    std::vector<std::pair<std::string, ReflectionFlickerMetrics>>& f = result.flicker_rows;
    for (DepthMethod m : kDepthMethods)
      f.emplace_back(depthMethodName(m), flicker->metrics(std::size_t(m) + 1));
    f.emplace_back("nobody", flicker->metrics(FlickerRun::kNobody));
    f.emplace_back("true depth on the mask", flicker->metrics(FlickerRun::kTruthOnMask));
    f.emplace_back("true depth on ours' pixels", flicker->metrics(FlickerRun::kTruthOnOurs));
    f.emplace_back("truth", flicker->metrics(FlickerRun::kTruth));
    for (const auto& [name, m] : f) flicker_methods[name] = toJson(m);
    const auto& raw = f[std::size_t(DepthMethod::Raw)].second;
    const auto& taa = f[std::size_t(DepthMethod::Taa)].second;
    for (std::size_t i :
         {std::size_t(DepthMethod::Ours), std::size_t(DepthMethod::Adversary), kDepthMethods.size()}) {
      const FlickerBarVerdicts v = checkFlickerBars(f[i].second, raw, taa);
      flicker_bars[f[i].first] = {{"below_raw", v.below_raw}, {"below_taa", v.below_taa}, {"all", v.all()}};
    }
    const int view_size = o.view_size > 0 ? o.view_size : pipeline::FrameLoopOptions{}.view_size;
    result.report["reflection_flicker"] = {
        {"view_size", view_size},
        {"views", 4},
        {"units", "squared 8-bit display levels"},
        {"methods", flicker_methods},
        {"bars", flicker_bars},
        {"raw_over_ours", raw.flicker / f[std::size_t(DepthMethod::Ours)].second.flicker},
        {"taa_over_ours", taa.flicker / f[std::size_t(DepthMethod::Ours)].second.flicker}};
    if (o.figure) {
      std::vector<std::pair<std::string, ReflectionFlickerMetrics>> shown_series;
      for (DepthMethod m : {DepthMethod::Ours, DepthMethod::Raw, DepthMethod::Median, DepthMethod::Taa})
        shown_series.push_back(f[std::size_t(m)]);
      result.flicker_figure = flickerFigure(
          shown_series, "displayed reflection flicker per frame pair (levels^2), " + description.name);
    }
  }
  if (o.figure)
    result.figure =
        depthMethodsFigure(museum, figure_camera, figure_frame, streams[std::size_t(figure_camera)]);
  return result;
}

}  // namespace holo::eval
