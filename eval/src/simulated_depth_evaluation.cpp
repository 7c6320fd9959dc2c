#include "holo/eval/simulated_depth_evaluation.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "figure_label.hpp"
#include "holo/core/progress.hpp"
#include "holo/depthfilter/cloud_view.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/sim/museum.hpp"

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
  config.mask.keep_attached_limbs = o.keep_attached_limbs;
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
  for (int c = 0; c < museum.cameraCount(); ++c) cameras.push_back(museum.camera(c));
  depthfilter::CrossCameraFillConfig cross_config;
  cross_config.enabled = o.cross_camera;
  const depthfilter::CrossCameraFill cross_camera(cameras, cross_config);
  long filled = 0, confirmed = 0, camera_frames = 0;

  int figure_camera = 0;
  long figure_pixels = -1;
  sim::SimulatedFrame figure_frame;
  std::vector<sim::SimulatedFrame> frames(std::size_t(museum.cameraCount()));
  std::vector<depthfilter::CrossCameraView> views(frames.size());
  std::vector<depthfilter::CrossCameraCounts> counts;
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
      streams[std::size_t(c)].scoreFrame({f.frame, f.true_depth, f.foreground}, ours_depth[std::size_t(c)]);
      if (scored) {
        filled += counts[std::size_t(c)].filled;
        confirmed += counts[std::size_t(c)].confirmed;
        ++camera_frames;
      }
      if (t + 1 == total && cv::countNonZero(f.foreground) > figure_pixels) {
        figure_pixels = cv::countNonZero(f.foreground);
        figure_camera = c;
        figure_frame = std::move(f);
      }
    }
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
  for (DepthMethod m : {DepthMethod::Ours, DepthMethod::Adversary})
    bars[depthMethodName(m)] = toJson(checkDepthBars(
        combined(m), combined(DepthMethod::Raw), combined(DepthMethod::Median), combined(DepthMethod::Taa)));
  result.report = {
      {"scene", description.name},
      {"frames", o.frames},
      {"learning_frames", o.learning_frames},
      {"levels", o.levels},
      {"mask_persistence", o.mask_persistence},
      {"keep_attached_limbs", o.keep_attached_limbs},
      {"cross_camera", o.cross_camera},
      {"cross_camera_filled_per_camera_frame",
       camera_frames > 0 ? double(filled) / double(camera_frames) : 0.0},
      {"cross_camera_confirmed_per_camera_frame",
       camera_frames > 0 ? double(confirmed) / double(camera_frames) : 0.0},
      {"cameras", museum.cameraCount()},
      {"width", description.camera.width},
      {"height", description.camera.height},
      {"methods", methods},
      {"bars", bars},
      {"truth_depth_change_cm2", DepthFilterEvaluation::combinedTruth(streams).depth_change_cm2}};
  if (o.figure)
    result.figure =
        depthMethodsFigure(museum, figure_camera, figure_frame, streams[std::size_t(figure_camera)]);
  return result;
}

}  // namespace holo::eval
