// The depth filter on the simulated museum (sim module): masks against the true foreground and
// every method's Table 2 metrics against the true depth, at CI size (one camera, 320x180, 30
// scored frames). The full evaluation on every hall is `holopyramid eval depth` (docs/depthfilter.md).
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/depth_evaluation.hpp"
#include "holo/sim/museum.hpp"

namespace holo::eval {
namespace {

struct MaskScore {
  long tp = 0, predicted = 0, actual = 0;
  double precision() const { return predicted > 0 ? double(tp) / double(predicted) : 1.0; }
  double recall() const { return actual > 0 ? double(tp) / double(actual) : 1.0; }
};

bool meetsBars(const DepthMethodMetrics& m, const DepthMethodMetrics& raw, const DepthMethodMetrics& median,
               const DepthMethodMetrics& taa) {
  return checkDepthBars(m, raw, median, taa, kCiDepthBars).all();
}

// One camera of the default museum with the given visitors, run through the evaluation once per
// model and shared by the tests: the camera that sees the most visitor pixels at the start.
struct MuseumRun {
  static constexpr int kLearning = 10, kScored = 30;

  explicit MuseumRun(sim::VisitorModel model) {
    sim::SceneDescription description = sim::loadScene("museum");
    description.camera.width = 320;
    description.camera.height = 180;
    description.visitor_model = model;
    const sim::Museum museum(description);
    long best = -1;
    for (int c = 0; c < museum.cameraCount(); ++c) {
      const long n = cv::countNonZero(museum.renderCamera(c, 0).foreground);
      if (n > best) best = n, camera = c;
    }
    visitor_pixels = best;
    DepthEvaluationConfig config;
    config.filter.learning_frames = kLearning;
    depthfilter::TemporalDepthFilterConfig without_pull_push = config.filter;
    without_pull_push.levels = 1;
    depthfilter::TemporalDepthFilterConfig without_mask_edge_fill = config.filter;
    without_mask_edge_fill.fill_mask_edge = false;
    depthfilter::TemporalDepthFilterConfig with_precursor_surface_fill = config.filter;
    with_precursor_surface_fill.fill_on_precursor_surface = true;
    config.ours_variants = {without_pull_push, without_mask_edge_fill, with_precursor_surface_fill};

    evaluation = std::make_unique<DepthFilterEvaluation>(config);
    DepthEvaluationConfig without_persistence_config = config;
    without_persistence_config.ours_variants.clear();
    without_persistence_config.persistence.enabled = false;
    without_persistence = std::make_unique<DepthFilterEvaluation>(without_persistence_config);
    DepthEvaluationConfig without_limbs_config = config;
    without_limbs_config.ours_variants.clear();
    without_limbs_config.mask.keep_attached_limbs = false;
    without_limbs = std::make_unique<DepthFilterEvaluation>(without_limbs_config);
    DepthEvaluationConfig without_unread_config = config;
    without_unread_config.ours_variants.clear();
    without_unread_config.mask.background_adopt_frames = 1;
    without_unread_config.mask.unshrunk_colour_over_unread_background = false;
    without_unread_config.mask.unknown_background_growth_steps = 0;
    without_unread = std::make_unique<DepthFilterEvaluation>(without_unread_config);
    DepthEvaluationConfig without_growth_config = config;
    without_growth_config.ours_variants.clear();
    without_growth_config.mask.unknown_background_growth_steps = 0;
    without_growth = std::make_unique<DepthFilterEvaluation>(without_growth_config);
    DepthEvaluationConfig half_resolution_config = config;
    half_resolution_config.ours_variants.clear();
    half_resolution_config.foreground_scale = 2;
    half_resolution = std::make_unique<DepthFilterEvaluation>(half_resolution_config);
    DepthEvaluationConfig half_resolution_outline_config = half_resolution_config;
    half_resolution_outline_config.full_size_outline = true;
    half_resolution_outline = std::make_unique<DepthFilterEvaluation>(half_resolution_outline_config);
    HoleLeavingAdversary drop_changed_raw(config.adversary_max_change_m);
    for (int t = 0; t < 8; ++t) {
      const RgbdFrame background = museum.renderCamera(camera, t, false).frame;
      evaluation->learnBackground(background);
      without_persistence->learnBackground(background);
      without_limbs->learnBackground(background);
      without_unread->learnBackground(background);
      without_growth->learnBackground(background);
      half_resolution->learnBackground(background);
      half_resolution_outline->learnBackground(background);
    }
    cv::Mat first;
    for (int t = 0; t < kLearning + kScored; ++t) {
      const sim::SimulatedFrame f = museum.renderCamera(camera, t);
      const GroundTruthFrame truth{f.frame, f.true_depth, f.foreground};
      evaluation->addFrame(truth);
      without_persistence->addFrame(truth);
      without_limbs->addFrame(truth);
      without_unread->addFrame(truth);
      without_growth->addFrame(truth);
      half_resolution->addFrame(truth);
      half_resolution_outline->addFrame(truth);
      const cv::Mat& m = evaluation->lastMask();
      const cv::Mat raw_dropped = drop_changed_raw.apply(evaluation->lastOutput(DepthMethod::Raw));
      mask.tp += cv::countNonZero(m & f.foreground);
      mask.predicted += cv::countNonZero(m);
      mask.actual += cv::countNonZero(f.foreground);
      if (evaluation->learning() || t < kLearning) continue;
      raw_adversary.add(raw_dropped, truth);
      // Frozen: our first scored output, kept on the current mask.
      const cv::Mat ours = evaluation->lastOutput(DepthMethod::Ours);
      if (first.empty()) first = ours.clone();
      cv::Mat frozen_depth = cv::Mat::zeros(ours.size(), CV_32FC1);
      first.copyTo(frozen_depth, m);
      frozen.add(frozen_depth, truth);
      // Over-smoothed: our output averaged over 9x9 foreground pixels (normalised box filter).
      cv::Mat valid = ours > 0.0f, sum, count, smooth;
      valid.convertTo(valid, CV_32FC1, 1.0 / 255.0);
      cv::boxFilter(ours, sum, -1, cv::Size(9, 9), cv::Point(-1, -1), false);
      cv::boxFilter(valid, count, -1, cv::Size(9, 9), cv::Point(-1, -1), false);
      cv::divide(sum, cv::max(count, 1e-6f), smooth);
      smooth.setTo(0.0f, ours <= 0.0f);
      smoothed.add(smooth, truth);
    }
  }

  DepthMethodMetrics metrics(DepthMethod method) const { return evaluation->metrics(method); }

  // Ours' variants on the same masks and flow (config.ours_variants above).
  static constexpr std::size_t kWithoutPullPush = 0, kWithoutMaskEdgeFill = 1, kWithPrecursorSurfaceFill = 2;

  std::unique_ptr<DepthFilterEvaluation> evaluation;
  std::unique_ptr<DepthFilterEvaluation> without_persistence;  // the same frames, the mask not persisting
  std::unique_ptr<DepthFilterEvaluation> without_limbs;  // the same frames, the opening's thin limbs lost
  // The same frames, an unread background depth adopted at once and decided by the shrunk colour,
  // the mask not grown (compared with without_growth).
  std::unique_ptr<DepthFilterEvaluation> without_unread;
  // The same frames, the mask not grown into readings of unknown background depth.
  std::unique_ptr<DepthFilterEvaluation> without_growth;
  // The same frames with every method on the half-size frames, scored at 320x180.
  std::unique_ptr<DepthFilterEvaluation> half_resolution;
  std::unique_ptr<DepthFilterEvaluation> half_resolution_outline;  // full_size_outline
  DepthScorer frozen, smoothed, raw_adversary;
  MaskScore mask;
  int camera = 0;
  long visitor_pixels = 0;
};

const MuseumRun& museumRun(sim::VisitorModel model) {
  static std::map<sim::VisitorModel, std::unique_ptr<MuseumRun>> runs;
  auto& run = runs[model];
  if (!run) run = std::make_unique<MuseumRun>(model);
  return *run;
}

void print(const char* name, const DepthMethodMetrics& r) {
  std::printf(
      "%-9s temporal %9.3f cm2 rmse %6.3f cm coverage %.4f hole pairs %.4f (raw holes %.3f) ghost %.4f "
      "change %8.3f cm2 sensor %.2f cm %.2f cm2 %.2f ms\n",
      name, r.temporal_mse_cm2, r.depth_rmse_cm, r.coverage, r.hole_pair_ratio, r.raw_holes_filled,
      r.ghost_ratio, r.depth_change_cm2, r.sensor_rmse_cm, r.sensor_temporal_mse_cm2, r.ms_per_frame);
}

class SimulatedMuseum : public ::testing::TestWithParam<sim::VisitorModel> {
 protected:
  const MuseumRun& run() const { return museumRun(GetParam()); }
};

TEST_P(SimulatedMuseum, MaskFindsTheVisitors) {
  const MuseumRun& r = run();
  ASSERT_GT(r.visitor_pixels, 320 * 180 / 100) << "no visitor in view";
  std::printf("camera %d mask precision %.4f recall %.4f\n", r.camera, r.mask.precision(), r.mask.recall());
  EXPECT_GT(r.mask.precision(), 0.95);
  EXPECT_GT(r.mask.recall(), 0.95);
}

// Every method's figures; the truth itself has zero temporal error, and its literal
// frame-to-frame change (the visitors' real motion) is far above ours' temporal error: why the
// literal change cannot be the temporal bar with walking visitors.
TEST_P(SimulatedMuseum, OursIsSteadierThanRawMedianAndTaaAndNearerTheTruthThanRaw) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours), raw = r.metrics(DepthMethod::Raw);
  for (DepthMethod m : kDepthMethods) print(depthMethodName(m), r.metrics(m));
  print("truth", r.evaluation->truthMetrics());
  EXPECT_EQ(ours.scored_frames, MuseumRun::kScored);
  const DepthBarVerdicts verdicts =
      checkDepthBars(ours, raw, r.metrics(DepthMethod::Median), r.metrics(DepthMethod::Taa), kCiDepthBars);
  EXPECT_TRUE(verdicts.below_median);
  EXPECT_TRUE(verdicts.below_taa);
  EXPECT_TRUE(verdicts.rmse_below_raw);
  EXPECT_TRUE(verdicts.ghosts);
  EXPECT_GT(ours.coverage, raw.coverage);
  EXPECT_EQ(r.evaluation->truthMetrics().temporal_mse_cm2, 0.0);
  EXPECT_GT(r.evaluation->truthMetrics().depth_change_cm2, 3.0 * ours.temporal_mse_cm2);
}

// The two bars the default visitors do not meet yet are held on the figures: 5x below raw's
// temporal error and the CI coverage. With the bodies ours is 3.4x below raw (7.69 against 26.3
// cm^2; the holes alone cost ~3.9 of the 5.3 cm^2 the bar allows) at coverage 0.894 (the mask
// misses pixels where the sensor reads nothing, and wrong fills remain where optical flow carries
// a limb's depth into an uncovered gap): docs/depthfilter.md, "Simulated halls".
TEST(SimulatedMuseumFigures, OursMeetsEveryBarAgainstRawMedianAndTaa) {
  const MuseumRun& r = museumRun(sim::VisitorModel::figures);
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours), raw = r.metrics(DepthMethod::Raw);
  EXPECT_TRUE(meetsBars(ours, raw, r.metrics(DepthMethod::Median), r.metrics(DepthMethod::Taa)));
  EXPECT_LT(ours.temporal_mse_cm2 * kCiFiguresBelowRaw, raw.temporal_mse_cm2);
}

TEST(SimulatedMuseumBodies, OursIsAtLeastThreeTimesSteadierThanRaw) {
  const MuseumRun& r = museumRun(sim::VisitorModel::bodies);
  EXPECT_LT(r.metrics(DepthMethod::Ours).temporal_mse_cm2 * kCiBodiesBelowRaw,
            r.metrics(DepthMethod::Raw).temporal_mse_cm2);
}

// The pull-push on the same masks and flow: switched off (l_max 1), the interior holes wider
// than the colour-guided fill's reach stay holes, so the output covers less of the visitors,
// fills fewer of the sensor's holes and is less steady. (The gain is small: with the between-
// surfaces and silhouette rules most holes are not the push's to fill; docs/depthfilter.md.)
TEST_P(SimulatedMuseum, SwitchingThePullPushOffMakesOursWorse) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours),
                           off = r.evaluation->variantMetrics(MuseumRun::kWithoutPullPush);
  print("ours", ours);
  print("l_max 1", off);

  EXPECT_GE(depthfilter::TemporalDepthFilterConfig{}.levels, 3);
  EXPECT_GT(ours.coverage, off.coverage + 0.001);
  EXPECT_GT(ours.raw_holes_filled, off.raw_holes_filled + 0.01);
  EXPECT_LT(ours.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(ours.depth_rmse_cm, off.depth_rmse_cm * 1.02);
}

// Without the mask's persistence, the visitor pixels where the sensor reads nothing and colour
// misses the visitor fall out of the mask and stay holes: fewer of the sensor's holes are filled
// and the coverage drops, with no more ghosts than the bar allows.
TEST_P(SimulatedMuseum, SwitchingTheMaskPersistenceOffMakesOursWorse) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours);
  const DepthMethodMetrics off = r.without_persistence->metrics(DepthMethod::Ours);
  print("ours", ours);
  print("no persist", off);
  EXPECT_LE(ours.ghost_ratio, off.ghost_ratio * 1.2);
  EXPECT_TRUE(depthfilter::MaskPersistenceConfig{}.enabled);
  EXPECT_GT(ours.coverage, off.coverage + 0.005);
  EXPECT_GT(ours.raw_holes_filled, off.raw_holes_filled + 0.04);
  EXPECT_LT(ours.ghost_ratio, DepthBars{}.ghosts);
}

// Without keep_attached_limbs the mask's opening removes the limbs one or two pixels wide (arms,
// fingers, the far leg at this size): their measured pixels fall out of the mask, so ours covers
// less of the visitors and, those pixels scoring as holes, is less steady.
TEST_P(SimulatedMuseum, SwitchingTheAttachedLimbsOffMakesOursWorse) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours);
  const DepthMethodMetrics off = r.without_limbs->metrics(DepthMethod::Ours);
  print("ours", ours);
  print("no limbs", off);
  EXPECT_TRUE(depthfilter::ForegroundMaskConfig{}.keep_attached_limbs);
  // With the unshrunk colour where the background depth is unknown (foreground_mask.hpp) part of
  // the limbs returns without it too: +0.001 coverage on this camera.
  EXPECT_GT(ours.coverage, off.coverage + 0.0005);
  EXPECT_LT(ours.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(ours.depth_rmse_cm, off.depth_rmse_cm);
  EXPECT_LT(ours.ghost_ratio, DepthBars{}.ghosts);
}

// Where the empty hall read no depth (the floor at a grazing angle), a visitor's edge that the
// shrunk colour labels missed was adopted as the background at once, and the visitor was
// background there whenever it passed again. Without the adoption's wait and the unshrunk colour
// ours covers less.
TEST_P(SimulatedMuseum, SwitchingTheUnreadBackgroundRulesOffMakesOursWorse) {
  const MuseumRun& r = run();
  // Both without the mask's growth into unknown background: grown, the mask takes most of the
  // same pixels on this camera, and the rules add nothing more there (docs/depthfilter.md).
  const DepthMethodMetrics ours = r.without_growth->metrics(DepthMethod::Ours);
  const DepthMethodMetrics off = r.without_unread->metrics(DepthMethod::Ours);
  print("no growth", ours);
  print("no unread", off);
  EXPECT_EQ(depthfilter::ForegroundMaskConfig{}.background_adopt_frames, 30);
  EXPECT_TRUE(depthfilter::ForegroundMaskConfig{}.unshrunk_colour_over_unread_background);
  // This camera sees little floor beyond the sensor's grazing angle: the gain is small here
  // (+0.002 coverage) and larger on the four cameras of a hall (docs/depthfilter.md).
  EXPECT_GT(ours.coverage, off.coverage + 0.001);
  EXPECT_LT(ours.temporal_mse_cm2, off.temporal_mse_cm2);
  EXPECT_LT(ours.ghost_ratio, DepthBars{}.ghosts);
}

// The foreground at half resolution (depthfilter/foreground_scale.hpp), scored at the camera's:
// each reduced pixel's output repeated over its 2x2 block, every true visitor pixel counted, so a
// block the reduced foreground misses costs all four of its pixels.
TEST_P(SimulatedMuseum, HalfResolutionForegroundCoversTheVisitorsWithinAMarginOfFullResolution) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours);
  const DepthMethodMetrics half = r.half_resolution->metrics(DepthMethod::Ours);
  print("ours", ours);
  print("half", half);
  print("half raw", r.half_resolution->metrics(DepthMethod::Raw));
  EXPECT_EQ(half.scored_frames, ours.scored_frames);
  // Measured: 0.9128 -> 0.8745 (bodies), 0.9306 -> 0.8994 (figures). The blocks at the visitors'
  // outlines are what it loses, and what overhangs them it pays as ghosts (0.0025 -> 0.018,
  // 0.0040 -> 0.031: above the bar, docs/depthfilter.md "Speed").
  EXPECT_GT(half.coverage, ours.coverage - 0.05);
  EXPECT_LT(half.coverage, ours.coverage);
  EXPECT_GT(half.ghost_ratio, ours.ghost_ratio);
}

// The half-resolution foreground with its outline and depth edges redrawn from the camera's own
// readings (depthfilter/full_size_outline.hpp) against the same foreground repeated over its
// blocks: it covers more of the visitors, outputs fewer ghosts and errs less, frame to frame and
// against the truth (still short of the camera's resolution: docs/depthfilter.md "Speed").
TEST_P(SimulatedMuseum, TheFullSizeOutlineWinsBackWhatHalfResolutionLosesAtTheOutlines) {
  const MuseumRun& r = run();
  const DepthMethodMetrics half = r.half_resolution->metrics(DepthMethod::Ours);
  const DepthMethodMetrics outline = r.half_resolution_outline->metrics(DepthMethod::Ours);
  print("half", half);
  print("half outline", outline);
  EXPECT_EQ(outline.scored_frames, half.scored_frames);
  EXPECT_GT(outline.coverage, half.coverage);
  // Measured: coverage 0.881 -> 0.908 (bodies), 0.904 -> 0.933 (figures); ghosts 0.0188 -> 0.0071,
  // 0.0317 -> 0.0101; temporal MSE' 20.0 -> 13.0, 39.9 -> 21.8 cm^2.
  EXPECT_LT(outline.ghost_ratio, 0.8 * half.ghost_ratio);
  EXPECT_LT(outline.depth_rmse_cm, half.depth_rmse_cm);
  EXPECT_LT(outline.temporal_mse_cm2, half.temporal_mse_cm2);
}

// A hole at the mask's edge (the visitor's silhouette, where a structured-light sensor reads
// nothing at grazing angles) without a trusted precursor stayed a hole. Filled from the farthest
// measured neighbour of its colour inside the mask, all on one surface, ours covers more of the
// visitors; with the default (articulated) visitors, those pixels no longer scoring as holes, it
// is also steadier. On the box-and-cylinder figures the fills' own frame-to-frame error outweighs
// the holes on this camera (4.73 -> 5.89 cm^2, docs/depthfilter.md), bounded here.
TEST_P(SimulatedMuseum, SwitchingTheMaskEdgeFillOffMakesOursWorse) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours);
  const DepthMethodMetrics off = r.evaluation->variantMetrics(MuseumRun::kWithoutMaskEdgeFill);
  print("ours", ours);
  print("no edge", off);
  EXPECT_TRUE(depthfilter::TemporalDepthFilterConfig{}.fill_mask_edge);
  EXPECT_GT(ours.coverage, off.coverage + 0.005);
  EXPECT_GT(ours.raw_holes_filled, off.raw_holes_filled + 0.02);
  if (GetParam() == sim::VisitorModel::bodies)
    EXPECT_LT(ours.temporal_mse_cm2, off.temporal_mse_cm2);
  else
    EXPECT_LT(ours.temporal_mse_cm2, 1.4 * off.temporal_mse_cm2);
  EXPECT_LT(ours.ghost_ratio, DepthBars{}.ghosts);
}

// A hole with a trusted precursor whose neighbours of its colour span two surfaces stays a hole.
// Taking those on the precursor's surface covers more, but 35-41% of those fills lie on the
// wrong surface and they flicker (docs/depthfilter.md): ours is steadier without it, which is
// why it is off.
TEST_P(SimulatedMuseum, ThePrecursorSurfaceFillMakesOursLessSteady) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours);
  const DepthMethodMetrics on = r.evaluation->variantMetrics(MuseumRun::kWithPrecursorSurfaceFill);
  print("ours", ours);
  print("pre fill", on);
  EXPECT_FALSE(depthfilter::TemporalDepthFilterConfig{}.fill_on_precursor_surface);
  EXPECT_GT(on.coverage, ours.coverage);
  EXPECT_LT(ours.temporal_mse_cm2 * 1.2, on.temporal_mse_cm2);
}

TEST_P(SimulatedMuseum, FrozenOrOverSmoothedDepthFailsTheBars) {
  const MuseumRun& r = run();
  const DepthMethodMetrics raw = r.metrics(DepthMethod::Raw), median = r.metrics(DepthMethod::Median),
                           taa = r.metrics(DepthMethod::Taa);
  const DepthMethodMetrics frozen = r.frozen.metrics(), smoothed = r.smoothed.metrics();
  print("frozen", frozen);
  print("smoothed", smoothed);
  EXPECT_FALSE(meetsBars(frozen, raw, median, taa));
  EXPECT_FALSE(meetsBars(smoothed, raw, median, taa));
  EXPECT_GT(frozen.depth_rmse_cm, raw.depth_rmse_cm);
  EXPECT_GT(smoothed.depth_rmse_cm, r.metrics(DepthMethod::Ours).depth_rmse_cm);
}

// The hole-leaving adversary, on ours (DepthMethod::Adversary) and on raw: leaving a hole wherever
// the depth moved must not buy a better temporal figure than ours, nor pass the bars.
TEST_P(SimulatedMuseum, LeavingHolesWhereTheDepthMovesFailsTheBars) {
  const MuseumRun& r = run();
  const DepthMethodMetrics ours = r.metrics(DepthMethod::Ours), raw = r.metrics(DepthMethod::Raw),
                           median = r.metrics(DepthMethod::Median), taa = r.metrics(DepthMethod::Taa);
  const DepthMethodMetrics on_ours = r.metrics(DepthMethod::Adversary), on_raw = r.raw_adversary.metrics();
  print("adv ours", on_ours);
  print("adv raw", on_raw);
  EXPECT_FALSE(meetsBars(on_ours, raw, median, taa));
  EXPECT_FALSE(meetsBars(on_raw, raw, median, taa));
  EXPECT_GT(on_ours.temporal_mse_cm2, ours.temporal_mse_cm2);
  EXPECT_GT(on_ours.depth_rmse_cm, ours.depth_rmse_cm);
}

// Where the empty hall read no depth, a visitor whose colour matches the hall is read by the
// sensor but only the colour decides, and misses it. Grown from the mask along the visitor's
// surface into those readings, the mask covers more of the visitors and ours is steadier. The
// mirror hall, the default bodies, at CI size (measured 0.877 -> 0.957 coverage, 90.7 -> 34.2 cm^2).
TEST(SimulatedMirror, SwitchingTheMaskGrowthOffMakesOursWorse) {
  constexpr int kLearning = 10, kScored = 20;
  sim::SceneDescription description = sim::loadScene("mirror");
  description.camera.width = 320;
  description.camera.height = 180;
  const sim::Museum museum(description);
  // Camera 1 sees the visitors over floor the empty hall did not read; on camera 0 the growth
  // changes the coverage by 0.0001, cameras 2 and 3 see nobody in these frames.
  constexpr int camera = 1;
  DepthEvaluationConfig config;
  config.filter.learning_frames = kLearning;
  DepthEvaluationConfig without_config = config;
  without_config.mask.unknown_background_growth_steps = 0;
  DepthFilterEvaluation grown(config), without(without_config);
  for (int t = 0; t < 8; ++t) {
    const RgbdFrame background = museum.renderCamera(camera, t, false).frame;
    grown.learnBackground(background);
    without.learnBackground(background);
  }
  for (int t = 0; t < kLearning + kScored; ++t) {
    const sim::SimulatedFrame f = museum.renderCamera(camera, t);
    grown.addFrame({f.frame, f.true_depth, f.foreground});
    without.addFrame({f.frame, f.true_depth, f.foreground});
  }
  const DepthMethodMetrics ours = grown.metrics(DepthMethod::Ours);
  const DepthMethodMetrics off = without.metrics(DepthMethod::Ours);
  print("ours", ours);
  print("no growth", off);
  EXPECT_GT(depthfilter::ForegroundMaskConfig{}.unknown_background_growth_steps, 0);
  EXPECT_GT(ours.coverage, off.coverage + 0.05);
  EXPECT_LT(ours.temporal_mse_cm2, 0.6 * off.temporal_mse_cm2);
  EXPECT_LT(ours.ghost_ratio, DepthBars{}.ghosts);
}

INSTANTIATE_TEST_SUITE_P(Visitors, SimulatedMuseum,
                         ::testing::Values(sim::VisitorModel::bodies, sim::VisitorModel::figures),
                         [](const ::testing::TestParamInfo<sim::VisitorModel>& model) {
                           return sim::visitorModelNames()[std::size_t(model.param)];
                         });

}  // namespace
}  // namespace holo::eval
