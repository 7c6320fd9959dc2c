// The cameras filling each other's holes (depthfilter::CrossCameraFill) on the simulated atrium
// at CI size (320x180, default visitors and sensor): cameras 1 and 2, whose shared wedge holds
// visitors in these frames, each through its mask, flow, persistence and our filter; our filter
// runs twice on the same masks and flow, once on the depth the other camera completed (and the
// mask it grew), once on the camera's own. Switched off, the holes on visitors the neighbour sees
// stay holes: ours covers less, fills fewer of the sensor's holes and is less steady. The full
// evaluation on every hall and camera is `holopyramid eval depth --cross-camera true|false`
// (docs/depthfilter.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/other_camera_witness.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/depth_evaluation.hpp"
#include "holo/sim/museum.hpp"

namespace holo::eval {
namespace {

void print(const char* name, const DepthMethodMetrics& m) {
  std::printf("%s temporal %.3f cm2 rmse %.3f cm coverage %.4f raw holes filled %.4f ghosts %.4f\n", name,
              m.temporal_mse_cm2, m.depth_rmse_cm, m.coverage, m.raw_holes_filled, m.ghost_ratio);
}

TEST(SimulatedCrossCamera, SwitchingTheCamerasFillingEachOtherOffMakesOursWorse) {
  constexpr int kLearning = 8, kScored = 12;
  const std::vector<int> cameras = {1, 2};
  sim::SceneDescription description = sim::loadScene("atrium");
  description.camera.width = 320;
  description.camera.height = 180;
  const sim::Museum museum(description);

  struct Camera {
    depthfilter::ForegroundMasker masker;
    depthfilter::PrecursorFlow flow;
    depthfilter::MaskPersistence persistence;
    depthfilter::TemporalDepthFilter helped, alone;
    DepthScorer helped_score, alone_score;
    cv::Mat previous_colour;
  };
  depthfilter::TemporalDepthFilterConfig filter_config;
  filter_config.learning_frames = kLearning;
  std::vector<Camera> streams;
  std::vector<CameraModel> models;
  for (int c : cameras) {
    streams.push_back({depthfilter::ForegroundMasker(), depthfilter::PrecursorFlow(),
                       depthfilter::MaskPersistence(), depthfilter::TemporalDepthFilter(filter_config),
                       depthfilter::TemporalDepthFilter(filter_config), DepthScorer(), DepthScorer(),
                       cv::Mat()});
    models.push_back(museum.camera(c));
    for (int t = 0; t < 8; ++t) streams.back().masker.learnBackground(museum.renderCamera(c, t, false).frame);
  }
  depthfilter::CrossCameraFillConfig step;
  step.enabled = true;
  const depthfilter::CrossCameraFill fill(models, step);
  long filled = 0;
  for (int t = 0; t < kLearning + kScored; ++t) {
    std::vector<sim::SimulatedFrame> frames;
    std::vector<cv::Mat> own_masks, flows;
    std::vector<depthfilter::CrossCameraView> views;
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      Camera& s = streams[i];
      frames.push_back(museum.renderCamera(cameras[i], t));
      const RgbdFrame& frame = frames.back().frame;
      cv::Mat mask = s.masker.apply(frame);
      flows.push_back(s.flow.compute(frame.colour, s.previous_colour));
      s.persistence.extend(mask, frame, flows.back());
      s.previous_colour = frame.colour.clone();
      own_masks.push_back(mask.clone());
      views.push_back({frame.depth, mask, s.masker.backgroundDepth()});
    }
    std::vector<depthfilter::CrossCameraCounts> counts;
    const std::vector<cv::Mat> depth = fill.apply(views, &counts);
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      Camera& s = streams[i];
      const sim::SimulatedFrame& f = frames[i];
      const bool scored = !s.helped.learning();
      const cv::Mat helped = s.helped.apply({f.frame.colour, depth[i], views[i].mask, flows[i]});
      const cv::Mat alone = s.alone.apply({f.frame.colour, f.frame.depth, own_masks[i], flows[i]});
      if (!scored) continue;
      filled += counts[i].filled;
      s.helped_score.add(helped, {f.frame, f.true_depth, f.foreground});
      s.alone_score.add(alone, {f.frame, f.true_depth, f.foreground});
    }
  }
  DepthScorer helped, alone;
  for (const Camera& s : streams) helped.merge(s.helped_score), alone.merge(s.alone_score);
  const DepthMethodMetrics on = helped.metrics(), off = alone.metrics();
  print("cross-camera on: ", on);
  print("cross-camera off:", off);
  std::printf("filled %.1f pixels per camera frame\n", double(filled) / double(kScored * cameras.size()));

  EXPECT_EQ(on.scored_frames, long(kScored * cameras.size()));
  EXPECT_GT(filled, 10L * kScored);
  EXPECT_GT(on.coverage, off.coverage + 0.001);
  EXPECT_GT(on.raw_holes_filled, off.raw_holes_filled + 0.01);
  EXPECT_LT(on.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(on.depth_rmse_cm, off.depth_rmse_cm * 1.01);
  // The CI size's bound: the mask's growth into unknown background (8 px, here at half the
  // camera's resolution) takes the atrium's ghosts on these cameras to 0.0078 with the step,
  // 0.0068 without; the full-size halls hold 0.005 (docs/depthfilter.md, "Simulated halls").
  EXPECT_LT(on.ghost_ratio, kCiDepthBars.ghosts);
  EXPECT_LT(on.ghost_ratio, off.ghost_ratio * 1.2);
}

// The other cameras deciding which of two surfaces of its colour a hole shows
// (depthfilter::OtherCameraWitness, TemporalDepthFilterConfig::fill_witnessed): the same cameras,
// masks, flow and sensor depth, our filter with and without the witness. Without it, those holes
// (an arm in front of the torso, two legs, the mask's edge) stay holes: ours covers less.
TEST(SimulatedCrossCamera, SwitchingTheWitnessedFillOffLeavesMoreHoles) {
  constexpr int kLearning = 8, kScored = 12;
  const std::vector<int> cameras = {1, 2};
  sim::SceneDescription description = sim::loadScene("atrium");
  description.camera.width = 320;
  description.camera.height = 180;
  const sim::Museum museum(description);

  struct Camera {
    depthfilter::ForegroundMasker masker;
    depthfilter::PrecursorFlow flow;
    depthfilter::MaskPersistence persistence;
    depthfilter::TemporalDepthFilter witnessed, alone;
    DepthScorer witnessed_score, alone_score;
    cv::Mat previous_colour;
  };
  depthfilter::TemporalDepthFilterConfig filter_config;
  filter_config.learning_frames = kLearning;
  std::vector<Camera> streams;
  std::vector<CameraModel> models;
  for (int c : cameras) {
    streams.push_back({depthfilter::ForegroundMasker(), depthfilter::PrecursorFlow(),
                       depthfilter::MaskPersistence(), depthfilter::TemporalDepthFilter(filter_config),
                       depthfilter::TemporalDepthFilter(filter_config), DepthScorer(), DepthScorer(),
                       cv::Mat()});
    models.push_back(museum.camera(c));
    for (int t = 0; t < 8; ++t) streams.back().masker.learnBackground(museum.renderCamera(c, t, false).frame);
  }
  const depthfilter::OtherCameraWitnesses witnesses(models);
  for (int t = 0; t < kLearning + kScored; ++t) {
    std::vector<sim::SimulatedFrame> frames;
    std::vector<cv::Mat> flows;
    std::vector<depthfilter::CrossCameraView> views;
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      Camera& s = streams[i];
      frames.push_back(museum.renderCamera(cameras[i], t));
      const RgbdFrame& frame = frames.back().frame;
      cv::Mat mask = s.masker.apply(frame);
      flows.push_back(s.flow.compute(frame.colour, s.previous_colour));
      s.persistence.extend(mask, frame, flows.back());
      s.previous_colour = frame.colour.clone();
      views.push_back({frame.depth, mask, s.masker.backgroundDepth()});
    }
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      Camera& s = streams[i];
      const sim::SimulatedFrame& f = frames[i];
      const bool scored = !s.witnessed.learning();
      const depthfilter::OtherCameraWitness witness = witnesses.witnessFor(views, i);
      const cv::Mat witnessed =
          s.witnessed.apply({f.frame.colour, f.frame.depth, views[i].mask, flows[i], &witness});
      const cv::Mat alone = s.alone.apply({f.frame.colour, f.frame.depth, views[i].mask, flows[i]});
      if (!scored) continue;
      s.witnessed_score.add(witnessed, {f.frame, f.true_depth, f.foreground});
      s.alone_score.add(alone, {f.frame, f.true_depth, f.foreground});
    }
  }
  DepthScorer witnessed, alone;
  for (const Camera& s : streams) witnessed.merge(s.witnessed_score), alone.merge(s.alone_score);
  const DepthMethodMetrics on = witnessed.metrics(), off = alone.metrics();
  print("witnessed fill on: ", on);
  print("witnessed fill off:", off);

  EXPECT_EQ(on.scored_frames, long(kScored * cameras.size()));
  EXPECT_GT(on.coverage, off.coverage + 0.001);
  EXPECT_GT(on.raw_holes_filled, off.raw_holes_filled);
  EXPECT_LT(on.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(on.depth_rmse_cm, off.depth_rmse_cm * 1.05);
  EXPECT_LT(on.ghost_ratio, kCiDepthBars.ghosts);
}

}  // namespace
}  // namespace holo::eval
