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

constexpr int kLearning = 8, kScored = 12;

void print(const char* name, const DepthMethodMetrics& m) {
  std::printf("%s temporal %.3f cm2 rmse %.3f cm coverage %.4f raw holes filled %.4f ghosts %.4f\n", name,
              m.temporal_mse_cm2, m.depth_rmse_cm, m.coverage, m.raw_holes_filled, m.ghost_ratio);
}

// Cameras 1 and 2 of the atrium at CI size, each through its mask, flow and persistence, and our
// filter twice on the same input: once with the step under test, once without.
class AtriumCameraPair {
 public:
  AtriumCameraPair() : museum_(ciAtrium()) {
    depthfilter::TemporalDepthFilterConfig filter_config;
    filter_config.learning_frames = kLearning;
    for (int c : kCameras) {
      streams_.push_back({depthfilter::ForegroundMasker(), depthfilter::PrecursorFlow(),
                          depthfilter::MaskPersistence(), depthfilter::TemporalDepthFilter(filter_config),
                          depthfilter::TemporalDepthFilter(filter_config), DepthScorer(), DepthScorer(),
                          cv::Mat()});
      models_.push_back(museum_.camera(c));
      for (int t = 0; t < 8; ++t)
        streams_.back().masker.learnBackground(museum_.renderCamera(c, t, false).frame);
    }
  }

  // One frame of both cameras up to the filter: the simulated frames, each camera's own mask (the
  // view's may be grown by a cross-camera step), its flow and its view for the cross-camera steps.
  struct Frame {
    std::vector<sim::SimulatedFrame> frames;
    std::vector<cv::Mat> own_masks, flows;
    std::vector<depthfilter::CrossCameraView> views;
  };
  Frame capture(int t) {
    Frame out;
    for (std::size_t i = 0; i < streams_.size(); ++i) {
      Stream& s = streams_[i];
      out.frames.push_back(museum_.renderCamera(kCameras[i], t));
      const RgbdFrame& frame = out.frames.back().frame;
      cv::Mat mask = s.masker.apply(frame);
      out.flows.push_back(s.flow.compute(frame.colour, s.previous_colour));
      s.persistence.extend(mask, frame, out.flows.back());
      s.previous_colour = frame.colour.clone();
      out.own_masks.push_back(mask.clone());
      out.views.push_back({frame.depth, mask, s.masker.backgroundDepth()});
    }
    return out;
  }

  // Camera i's filter with and without the step; both scored once past the learning frames.
  // Returns whether they were scored.
  bool filter(std::size_t i, const sim::SimulatedFrame& f, const depthfilter::DepthFilterInput& with,
              const depthfilter::DepthFilterInput& without) {
    Stream& s = streams_[i];
    const bool scored = !s.with.learning();
    const cv::Mat a = s.with.apply(with);
    const cv::Mat b = s.without.apply(without);
    if (!scored) return false;
    s.with_score.add(a, {f.frame, f.true_depth, f.foreground});
    s.without_score.add(b, {f.frame, f.true_depth, f.foreground});
    return true;
  }

  DepthMethodMetrics with() const {
    DepthScorer all;
    for (const Stream& s : streams_) all.merge(s.with_score);
    return all.metrics();
  }
  DepthMethodMetrics without() const {
    DepthScorer all;
    for (const Stream& s : streams_) all.merge(s.without_score);
    return all.metrics();
  }
  const std::vector<CameraModel>& models() const { return models_; }
  static constexpr std::size_t kCameraCount = 2;

 private:
  static constexpr int kCameras[kCameraCount] = {1, 2};
  static sim::SceneDescription ciAtrium() {
    sim::SceneDescription description = sim::loadScene("atrium");
    description.camera.width = 320;
    description.camera.height = 180;
    return description;
  }
  struct Stream {
    depthfilter::ForegroundMasker masker;
    depthfilter::PrecursorFlow flow;
    depthfilter::MaskPersistence persistence;
    depthfilter::TemporalDepthFilter with, without;
    DepthScorer with_score, without_score;
    cv::Mat previous_colour;
  };
  const sim::Museum museum_;
  std::vector<Stream> streams_;
  std::vector<CameraModel> models_;
};

TEST(SimulatedCrossCamera, SwitchingTheCamerasFillingEachOtherOffMakesOursWorse) {
  AtriumCameraPair pair;
  depthfilter::CrossCameraFillConfig step;
  step.enabled = true;
  const depthfilter::CrossCameraFill fill(pair.models(), step);
  long filled = 0;
  for (int t = 0; t < kLearning + kScored; ++t) {
    AtriumCameraPair::Frame c = pair.capture(t);
    std::vector<depthfilter::CrossCameraCounts> counts;
    const std::vector<cv::Mat> depth = fill.apply(c.views, &counts);
    for (std::size_t i = 0; i < AtriumCameraPair::kCameraCount; ++i) {
      const sim::SimulatedFrame& f = c.frames[i];
      if (pair.filter(i, f, {f.frame.colour, depth[i], c.views[i].mask, c.flows[i]},
                      {f.frame.colour, f.frame.depth, c.own_masks[i], c.flows[i]}))
        filled += counts[i].filled;
    }
  }
  const DepthMethodMetrics on = pair.with(), off = pair.without();
  print("cross-camera on: ", on);
  print("cross-camera off:", off);
  std::printf("filled %.1f pixels per camera frame\n",
              double(filled) / double(kScored * AtriumCameraPair::kCameraCount));

  EXPECT_EQ(on.scored_frames, long(kScored * AtriumCameraPair::kCameraCount));
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
  AtriumCameraPair pair;
  const depthfilter::OtherCameraWitnesses witnesses(pair.models());
  for (int t = 0; t < kLearning + kScored; ++t) {
    const AtriumCameraPair::Frame c = pair.capture(t);
    for (std::size_t i = 0; i < AtriumCameraPair::kCameraCount; ++i) {
      const sim::SimulatedFrame& f = c.frames[i];
      const depthfilter::OtherCameraWitness witness = witnesses.witnessFor(c.views, i);
      pair.filter(i, f, {f.frame.colour, f.frame.depth, c.views[i].mask, c.flows[i], &witness},
                  {f.frame.colour, f.frame.depth, c.views[i].mask, c.flows[i]});
    }
  }
  const DepthMethodMetrics on = pair.with(), off = pair.without();
  print("witnessed fill on: ", on);
  print("witnessed fill off:", off);

  EXPECT_EQ(on.scored_frames, long(kScored * AtriumCameraPair::kCameraCount));
  EXPECT_GT(on.coverage, off.coverage + 0.001);
  EXPECT_GT(on.raw_holes_filled, off.raw_holes_filled);
  EXPECT_LT(on.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(on.depth_rmse_cm, off.depth_rmse_cm * 1.05);
  EXPECT_LT(on.ghost_ratio, kCiDepthBars.ghosts);
}

}  // namespace
}  // namespace holo::eval
