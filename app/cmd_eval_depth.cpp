// `holopyramid eval depth`: runs the simulated museum through the pull-push temporal depth filter
// and its baselines (raw, temporal median, TAA) and reports the paper's Table 2 metrics as JSON
// (docs/depthfilter.md); --images writes a Fig. 9-like picture of each method's point cloud.
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/progress.hpp"
#include "holo/depthfilter/cloud_view.hpp"
#include "holo/depthfilter/depth_evaluation.hpp"
#include "holo/sim/museum.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;
using namespace holo::depthfilter;

struct Options {
  std::string scene = "museum";
  int frames = 60;
  int width = 0;
  int height = 0;
  int learning_frames = TemporalDepthFilterConfig{}.learning_frames;
  std::string json;
  std::string images;
};

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

cv::Mat labelled(cv::Mat picture, const std::string& label) {
  cv::putText(picture, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 2);
  return picture;
}

// Colour frame, then each method's cloud and the truth, seen 0.8 m behind and 0.2 m to the right
// of the camera (the paper's Fig. 9 viewpoint).
void writeFigure(const fs::path& dir, const sim::Museum& museum, int camera, const sim::SimulatedFrame& frame,
                 const DepthFilterEvaluation& evaluation) {
  const Intrinsics& K = museum.camera(camera).intrinsics();
  const vec3 shift(0.2f, 0.0f, -0.8f);
  double far = 0.0;
  cv::minMaxLoc(frame.true_depth, nullptr, &far, nullptr, nullptr, evaluation.lastMask());
  const float far_m = std::max(1.0f, float(far));
  std::vector<cv::Mat> panels{labelled(frame.frame.colour.clone(), "camera " + std::to_string(camera))};
  for (DepthMethod m : {DepthMethod::Raw, DepthMethod::Median, DepthMethod::Taa, DepthMethod::Ours})
    panels.push_back(
        labelled(renderShiftedCloud(evaluation.lastOutput(m), K, shift, 0.3f, far_m), depthMethodName(m)));
  cv::Mat truth = cv::Mat::zeros(frame.true_depth.size(), CV_32FC1);
  frame.true_depth.copyTo(truth, frame.foreground);
  panels.push_back(labelled(renderShiftedCloud(truth, K, shift, 0.3f, far_m), "truth"));
  cv::Mat row;
  cv::hconcat(panels, row);
  fs::create_directories(dir);
  const fs::path path = dir / "depth_methods.png";
  std::vector<std::uint8_t> png;
  cv::imencode(".png", row, png);
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  std::cerr << "wrote " << path.string() << "\n";
}

int run(const Options& o) {
  if (o.frames < 1) throw InputError("", "--frames", "a number of frames >= 1", std::to_string(o.frames));
  if (o.learning_frames < 0)
    throw InputError("", "--learning-frames", "a number of frames >= 0", std::to_string(o.learning_frames));
  sim::SceneDescription description = sim::loadScene(o.scene);
  if (o.width > 0) description.camera.width = o.width;
  if (o.height > 0) description.camera.height = o.height;
  const sim::Museum museum(description);

  DepthEvaluationConfig config;
  config.filter.learning_frames = o.learning_frames;
  std::vector<DepthFilterEvaluation> streams;
  for (int c = 0; c < museum.cameraCount(); ++c) streams.emplace_back(config);
  constexpr int kBackgroundFrames = 8;
  const int total = o.learning_frames + o.frames;
  ProgressReporter progress(std::int64_t(museum.cameraCount()) * (kBackgroundFrames + total), "eval depth");
  for (int c = 0; c < museum.cameraCount(); ++c)
    for (int t = 0; t < kBackgroundFrames; ++t, progress.update())
      streams[std::size_t(c)].learnBackground(museum.renderCamera(c, t, false).frame);

  int figure_camera = 0;
  long figure_pixels = -1;
  sim::SimulatedFrame figure_frame;
  for (int t = 0; t < total; ++t)
    for (int c = 0; c < museum.cameraCount(); ++c, progress.update()) {
      sim::SimulatedFrame f = museum.renderCamera(c, t);
      streams[std::size_t(c)].addFrame({f.frame, f.true_depth, f.foreground});
      if (t + 1 == total && cv::countNonZero(f.foreground) > figure_pixels) {
        figure_pixels = cv::countNonZero(f.foreground);
        figure_camera = c;
        figure_frame = std::move(f);
      }
    }
  progress.done();

  nlohmann::json methods, bars;
  std::vector<std::pair<std::string, DepthMethodMetrics>> rows;
  for (DepthMethod m : kDepthMethods) {
    rows.emplace_back(depthMethodName(m), DepthFilterEvaluation::combined(streams, m));
    methods[depthMethodName(m)] = toJson(rows.back().second);
  }
  const auto combined = [&](DepthMethod m) { return rows[std::size_t(m)].second; };
  for (DepthMethod m : {DepthMethod::Ours, DepthMethod::Adversary})
    bars[depthMethodName(m)] = toJson(checkDepthBars(
        combined(m), combined(DepthMethod::Raw), combined(DepthMethod::Median), combined(DepthMethod::Taa)));
  const nlohmann::json report = {
      {"scene", description.name},
      {"frames", o.frames},
      {"learning_frames", o.learning_frames},
      {"cameras", museum.cameraCount()},
      {"width", description.camera.width},
      {"height", description.camera.height},
      {"methods", methods},
      {"bars", bars},
      {"truth_depth_change_cm2", DepthFilterEvaluation::combinedTruth(streams).depth_change_cm2}};
  std::cout << report.dump(2) << "\n";
  std::cerr << depthMetricsTable(rows);
  if (!o.json.empty()) writeFileAtomically(o.json, report.dump(2) + "\n");
  if (!o.images.empty())
    writeFigure(o.images, museum, figure_camera, figure_frame, streams[std::size_t(figure_camera)]);
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval depth",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.add_option("--scene", o->scene, "Built-in scene name or scene YAML file")->capture_default_str();
      sub.add_option("--frames", o->frames, "Scored frames after the learning frames")->capture_default_str();
      sub.add_option("--learning-frames", o->learning_frames, "Frames C that only learn the PDFs")
          ->capture_default_str();
      sub.add_option("--width", o->width, "Camera width (default: the scene's)");
      sub.add_option("--height", o->height, "Camera height (default: the scene's)");
      sub.add_option("--json", o->json, "Write the report to this JSON file");
      sub.add_option("--images", o->images, "Write depth_methods.png (Fig. 9-like) into this folder");
      return [o] { return run(*o); };
    },
    "Temporal depth filter vs raw, median and TAA on a simulated scene (paper Table 2)"});

}  // namespace holo::app
