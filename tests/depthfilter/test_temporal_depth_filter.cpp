#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "synthetic_filter_run.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

using test::erodedMask;
using test::quickFilterConfig;
using test::rawDepthOnMask;
using test::runOnSyntheticScene;
using test::SyntheticRunMetrics;

// Mean output depth minus truth over the eroded box, after feeding frames whose box depth
// follows `box_z(t)`.
std::vector<double> boxErrorsCm(const std::function<float(int)>& box_z, int frames) {
  test::SyntheticScene scene;
  TemporalDepthFilter filter(quickFilterConfig());
  PrecursorFlow flow;
  cv::Mat previous;
  std::vector<double> errors;
  for (int t = 0; t < frames; ++t) {
    scene.box_z = box_z(t);
    const test::SyntheticFrame f = scene.render(t, 21);
    const cv::Mat out =
        filter.apply({f.frame.colour, f.frame.depth, f.true_mask, flow.compute(f.frame.colour, previous)});
    previous = f.frame.colour;
    const cv::Mat box = erodedMask(f.box_mask, 3);
    cv::Mat valid = box & (out > 0.0f);
    errors.push_back(100.0 * (cv::mean(out, valid)[0] - double(scene.box_z)));
  }
  return errors;
}

TEST(TemporalDepthFilter, FollowsASuddenDepthStepWithoutFreezing) {
  const std::vector<double> errors = boxErrorsCm([](int t) { return t < 20 ? 2.0f : 1.7f; }, 26);
  EXPECT_LT(std::abs(errors[19]), 0.5);
  for (int t = 21; t < 26; ++t) EXPECT_LT(std::abs(errors[std::size_t(t)]), 1.0) << "frame " << t;
}

TEST(TemporalDepthFilter, LagOfASteadyApproachStaysBounded) {
  // 1 cm per frame towards the camera (0.3 m/s at 30 fps), after the learning frames.
  const std::vector<double> errors =
      boxErrorsCm([](int t) { return 2.0f - 0.01f * float(std::max(0, t - 12)); }, 50);
  for (int t = 20; t < 50; ++t) EXPECT_LT(std::abs(errors[std::size_t(t)]), 4.0) << "frame " << t;
}

TEST(TemporalDepthFilter, FrozenOrOversmoothedFiltersFailTheDeformationBar) {
  const test::SyntheticScene scene;
  const SyntheticRunMetrics m_raw = runOnSyntheticScene(scene, rawDepthOnMask, 12, 20);
  cv::Mat first;
  const SyntheticRunMetrics frozen = runOnSyntheticScene(
      scene,
      [&](const DepthFilterInput& in) {
        if (first.empty()) first = rawDepthOnMask(in);
        cv::Mat out = cv::Mat::zeros(in.depth.size(), CV_32FC1);
        first.copyTo(out, in.mask);
        return out;
      },
      12, 20);
  const SyntheticRunMetrics blurred = runOnSyntheticScene(
      scene,
      [&](const DepthFilterInput& in) {
        cv::Mat out;
        cv::blur(rawDepthOnMask(in), out, cv::Size(15, 15));
        out.setTo(0.0f, in.mask == 0);
        return out;
      },
      12, 20);
  EXPECT_GT(frozen.rmse_disc_cm, m_raw.rmse_disc_cm);
  EXPECT_GT(blurred.rmse_disc_cm, m_raw.rmse_disc_cm);
}

// Two flat surfaces side by side, 1.0 m (left, x < 32) and 1.5 m (right), with depth noise;
// the camera and the surfaces are still. A 2x2 hole aligned with the pull's 2x2 blocks stays
// in the left surface in every frame; from frame `edge_hole_from` on, pixels of the left
// surface right at the depth edge have no depth either.
cv::Mat twoSurfaceHoles(const cv::Vec3b& left_colour, const cv::Vec3b& right_colour, int frames,
                        int edge_hole_from, bool fill_on_precursor_surface = false,
                        const SurfaceWitness* witness = nullptr) {
  TemporalDepthFilterConfig config;
  config.learning_frames = 3;
  config.fill_on_precursor_surface = fill_on_precursor_surface;
  TemporalDepthFilter filter(config);
  const cv::Size size(64, 48);
  const cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  const cv::Mat flow = cv::Mat::zeros(size, CV_32FC2);
  cv::Mat colour(size, CV_8UC3, right_colour);
  colour(cv::Rect(0, 0, 32, 48)).setTo(left_colour);
  cv::RNG rng(7);
  cv::Mat out;
  for (int t = 0; t < frames; ++t) {
    cv::Mat depth(size, CV_32FC1, cv::Scalar(1.5f));
    depth(cv::Rect(0, 0, 32, 48)).setTo(1.0f);
    cv::Mat noise(size, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.003);
    depth += noise;
    depth(cv::Rect(10, 10, 2, 2)).setTo(0.0f);
    if (t >= edge_hole_from) depth(cv::Rect(31, 20, 1, 4)).setTo(0.0f);
    out = filter.apply({colour, depth, mask, flow, witness});
  }
  EXPECT_FALSE(filter.learning());
  return out;
}

TEST(TemporalDepthFilter, FillsABlockAlignedHoleAndAnEdgeHoleOfTheHolesColour) {
  // Red left, blue right: the edge hole has the left surface's colour and is filled from it.
  const cv::Mat out = twoSurfaceHoles({40, 40, 200}, {200, 40, 40}, 8, 6);
  for (int y = 10; y < 12; ++y)
    for (int x = 10; x < 12; ++x) EXPECT_NEAR(out.at<float>(y, x), 1.0f, 0.01f) << x << "," << y;
  for (int y = 20; y < 24; ++y) EXPECT_NEAR(out.at<float>(y, 31), 1.0f, 0.01f) << "edge row " << y;
}

TEST(TemporalDepthFilter, EdgeHoleBetweenSurfacesOfOneColourStaysAHole) {
  // Both surfaces grey: either could own the edge hole (an arm in front of the torso), and a
  // wrong pick flickers, so by default it stays a hole; the hole inside the left surface is still
  // filled. With fill_on_precursor_surface its precursor, measured a frame before on the left
  // surface, picks that one's neighbours.
  const cv::Mat out = twoSurfaceHoles({128, 128, 128}, {128, 128, 128}, 8, 6);
  const cv::Mat on = twoSurfaceHoles({128, 128, 128}, {128, 128, 128}, 8, 6, true);
  EXPECT_NEAR(out.at<float>(10, 10), 1.0f, 0.01f);
  EXPECT_NEAR(on.at<float>(10, 10), 1.0f, 0.01f);
  for (int y = 20; y < 24; ++y) {
    EXPECT_EQ(out.at<float>(y, 31), 0.0f) << "edge row " << y;
    EXPECT_NEAR(on.at<float>(y, 31), 1.0f, 0.01f) << "edge row " << y;
  }
}

// Another camera as a witness that sees one surface at `seen` m along every pixel's ray, sees
// through the space in front of it and cannot see behind it.
class OneSurfaceWitness final : public SurfaceWitness {
 public:
  explicit OneSurfaceWitness(float seen) : seen_(seen) {}
  Sighting sighting(int, int, float depth) const override {
    if (std::abs(depth - seen_) < 0.05f) return Sighting::Seen;
    return depth < seen_ ? Sighting::Empty : Sighting::Unknown;
  }

 private:
  float seen_;
};

TEST(TemporalDepthFilter, AWitnessDecidesWhichOfTwoSurfacesOfOneColourAnEdgeHoleShows) {
  // The grey edge hole of the test above: the other camera sees the far surface through the
  // space where the near one would be, or the near one; where it sees nothing it stays a hole.
  const OneSurfaceWitness far(1.5f), near(1.0f), nothing(9.0f);
  const cv::Mat to_far = twoSurfaceHoles({128, 128, 128}, {128, 128, 128}, 8, 6, false, &far);
  const cv::Mat to_near = twoSurfaceHoles({128, 128, 128}, {128, 128, 128}, 8, 6, false, &near);
  const cv::Mat undecided = twoSurfaceHoles({128, 128, 128}, {128, 128, 128}, 8, 6, false, &nothing);
  for (int y = 20; y < 24; ++y) {
    EXPECT_NEAR(to_far.at<float>(y, 31), 1.5f, 0.01f) << "edge row " << y;
    EXPECT_NEAR(to_near.at<float>(y, 31), 1.0f, 0.01f) << "edge row " << y;
    EXPECT_EQ(undecided.at<float>(y, 31), 0.0f) << "edge row " << y;
  }
}

// A visitor's side turning away at the mask's edge: the mask is the left half (x < 32), its
// depth 1.0 + 0.004 x m (with noise) and never measured in the last two columns (the grazing
// angle). The mask overhangs the visitor by one pixel in the upper half: there column 31 shows
// the hall's colour.
cv::Mat silhouetteHoles(bool fill_mask_edge) {
  TemporalDepthFilterConfig config;
  config.learning_frames = 3;
  config.fill_mask_edge = fill_mask_edge;
  TemporalDepthFilter filter(config);
  const cv::Size size(64, 48);
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  mask(cv::Rect(0, 0, 32, 48)).setTo(255);
  const cv::Mat flow = cv::Mat::zeros(size, CV_32FC2);
  cv::Mat colour(size, CV_8UC3, cv::Scalar(200, 60, 30));  // the hall
  colour(cv::Rect(0, 0, 32, 48)).setTo(cv::Scalar(40, 40, 200));
  colour(cv::Rect(31, 0, 1, 24)).setTo(cv::Scalar(200, 60, 30));
  cv::RNG rng(5);
  cv::Mat out;
  for (int t = 0; t < 8; ++t) {
    cv::Mat depth(size, CV_32FC1, cv::Scalar(3.0f)), noise(size, CV_32FC1);
    for (int x = 0; x < 32; ++x) depth.col(x).setTo(1.0f + 0.004f * float(x));
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.001);
    depth += noise;
    depth(cv::Rect(30, 0, 2, 48)).setTo(0.0f);
    out = filter.apply({colour, depth, mask, flow});
  }
  return out;
}

TEST(TemporalDepthFilter, MaskEdgeHolesTakeTheFarthestNeighbourOfTheirColour) {
  const cv::Mat with = silhouetteHoles(true), without = silhouetteHoles(false);
  for (int y = 4; y < 44; ++y) {
    // Column 30 (truth 1.120 m): behind the mean of its neighbours (1.112 m), as the surface is.
    EXPECT_GT(with.at<float>(y, 30), 1.1145f) << "row " << y;
    EXPECT_LT(with.at<float>(y, 30), 1.1215f) << "row " << y;
    EXPECT_EQ(without.at<float>(y, 30), 0.0f) << "row " << y;
  }
  // The overhang shows the hall's colour, which no measured neighbour has: no ghost.
  for (int y = 0; y < 24; ++y) EXPECT_EQ(with.at<float>(y, 31), 0.0f) << "row " << y;
  EXPECT_GT(with.at<float>(30, 31), 1.1145f);  // the visitor's own colour below it is filled
}

// A flat grey surface at 1.2 m with depth noise and an 8x8 hole that is never measured (no
// precursor to trust), in the middle of the mask; inside it a 4x4 patch of `patch_colour`.
cv::Mat wideInteriorHole(int levels, const cv::Vec3b& patch_colour) {
  TemporalDepthFilterConfig config;
  config.learning_frames = 3;
  config.levels = levels;
  TemporalDepthFilter filter(config);
  const cv::Size size(64, 48);
  const cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  const cv::Mat flow = cv::Mat::zeros(size, CV_32FC2);
  cv::Mat colour(size, CV_8UC3, cv::Scalar(128, 128, 128));
  colour(cv::Rect(29, 21, 4, 4)).setTo(patch_colour);
  cv::RNG rng(11);
  cv::Mat out;
  for (int t = 0; t < 8; ++t) {
    cv::Mat depth(size, CV_32FC1, cv::Scalar(1.2f)), noise(size, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.003);
    depth += noise;
    depth(cv::Rect(27, 19, 8, 8)).setTo(0.0f);
    out = filter.apply({colour, depth, mask, flow});
  }
  return out;
}

TEST(TemporalDepthFilter, PullPushFillsAnInteriorHoleWiderThanTheGuidedFill) {
  // The hole's centre lies 4 px from the nearest measurement, beyond fill_radius (3): only the
  // pull-push reaches it, and its fill lies on the surface.
  const cv::Mat with = wideInteriorHole(3, {128, 128, 128}), without = wideInteriorHole(1, {128, 128, 128});
  for (int y = 22; y < 24; ++y)
    for (int x = 30; x < 32; ++x) {
      EXPECT_NEAR(with.at<float>(y, x), 1.2f, 0.01f) << x << "," << y;
      EXPECT_EQ(without.at<float>(y, x), 0.0f) << x << "," << y;
    }
}

TEST(TemporalDepthFilter, PullPushLeavesAHoleOfAnotherColourUnfilled) {
  // A dark patch in the hole is not the surface around it (a bag in front of a coat, the gap
  // between two limbs): the push's fill comes from grey pixels and is not used there.
  const cv::Mat out = wideInteriorHole(3, {20, 20, 20});
  for (int y = 22; y < 24; ++y)
    for (int x = 30; x < 32; ++x) EXPECT_EQ(out.at<float>(y, x), 0.0f) << x << "," << y;
  EXPECT_NEAR(out.at<float>(20, 28), 1.2f, 0.01f);  // the grey rim of the hole is still filled
}

TEST(TemporalDepthFilter, LearningFramesPassTheMeasurementThrough) {
  const test::SyntheticScene scene;
  TemporalDepthFilter filter(quickFilterConfig());
  PrecursorFlow flow;
  cv::Mat previous;
  for (int t = 0; t < 10; ++t) {
    EXPECT_TRUE(filter.learning());
    const test::SyntheticFrame f = scene.render(t, 31);
    const DepthFilterInput in{f.frame.colour, f.frame.depth, f.true_mask,
                              flow.compute(f.frame.colour, previous)};
    previous = f.frame.colour;
    EXPECT_EQ(cv::norm(filter.apply(in), rawDepthOnMask(in), cv::NORM_INF), 0.0);
  }
  EXPECT_FALSE(filter.learning());
  EXPECT_GT(filter.confidencePdf().samples(), 1000);
  EXPECT_GT(filter.depthDifferencePdf().samples(), 1000);
  // The learned |d| distribution says that noise-sized differences are common.
  EXPECT_GT(filter.depthDifferencePdf().cdf(0.02f), 0.5f);
}

// The filter's per-pixel passes run on the mask's bounding box grown by their reach (the
// default); over the whole frame they must give the same output, frame after frame (the state
// carried between frames included), for masks that touch the image's edges, an empty mask, a full
// mask, a single pixel and a mask far from the one before.
TEST(TemporalDepthFilter, MaskBoxGivesTheWholeFrameOutput) {
  test::SyntheticScene scene;
  scene.disc_speed_px = 7.0f;  // leaves the image on the right during the run
  TemporalDepthFilterConfig boxed_config = quickFilterConfig(), full_config = quickFilterConfig();
  full_config.mask_box_only = false;
  TemporalDepthFilter boxed(boxed_config), full(full_config);
  PrecursorFlow flow;
  cv::Mat previous;
  long compared = 0;
  for (int t = 0; t < 30; ++t) {
    const test::SyntheticFrame f = scene.render(t, 51);
    cv::Mat mask = f.true_mask.clone();
    if (t == 12) mask.setTo(0);                                                    // empty
    if (t == 13 || t == 20) mask.setTo(255);                                       // full
    if (t == 14) mask(cv::Rect(0, 0, 40, 30)).setTo(255);                          // top-left corner too
    if (t == 15) mask(cv::Rect(mask.cols - 17, mask.rows - 9, 17, 9)).setTo(255);  // bottom-right corner
    if (t == 16) {                                                                 // a single pixel
      mask.setTo(0);
      mask.at<std::uint8_t>(91, 131) = 255;
    }
    const cv::Mat lambda = flow.compute(f.frame.colour, previous);
    previous = f.frame.colour;
    const DepthFilterInput in{f.frame.colour, f.frame.depth, mask, lambda};
    const cv::Mat a = boxed.apply(in), b = full.apply(in);
    ASSERT_EQ(boxed.learning(), full.learning()) << "frame " << t;
    ASSERT_EQ(cv::countNonZero(a), cv::countNonZero(b)) << "frame " << t;
    EXPECT_LE(cv::norm(a, b, cv::NORM_INF), 1e-5) << "frame " << t;  // metres: float round-off
    if (t == 12) {
      EXPECT_EQ(cv::countNonZero(a), 0);
    }
    compared += cv::countNonZero(b);
  }
  EXPECT_EQ(boxed.confidencePdf().samples(), full.confidencePdf().samples());
  EXPECT_GT(compared, 100000);  // the comparison covered real output, the full masks included
}

TEST(TemporalDepthFilter, HardInputsStayFinite) {
  const test::SyntheticScene scene;
  TemporalDepthFilter filter(quickFilterConfig());
  PrecursorFlow flow;
  cv::Mat previous;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (int t = 0; t < 24; ++t) {
    test::SyntheticFrame f = scene.render(t, 41);
    cv::Mat mask = f.true_mask;
    if (t == 14) mask = cv::Mat::zeros(mask.size(), CV_8UC1);            // empty mask
    if (t == 15) mask = cv::Mat(mask.size(), CV_8UC1, cv::Scalar(255));  // full mask
    if (t == 16) f.frame.depth.setTo(0.0f);                              // all depth invalid
    if (t == 17) f.frame.depth.setTo(nan);
    if (t == 18) f.frame.depth(cv::Rect(0, 0, 200, 100)).setTo(inf);
    if (t == 19) f.frame.depth(cv::Rect(0, 0, 200, 100)).setTo(-inf);
    cv::Mat lambda = flow.compute(f.frame.colour, previous);
    if (t == 20) lambda.setTo(cv::Scalar(nan, inf));  // broken flow
    previous = f.frame.colour;
    const cv::Mat out = filter.apply({f.frame.colour, f.frame.depth, mask, lambda});
    ASSERT_TRUE(cv::checkRange(out)) << "frame " << t;
    double lo = 0, hi = 0;
    cv::minMaxLoc(out, &lo, &hi);
    EXPECT_GE(lo, 0.0) << "frame " << t;
    EXPECT_LT(hi, 3.5) << "frame " << t;
    cv::Mat outside = out.clone();
    outside.setTo(0.0f, mask);
    EXPECT_EQ(cv::countNonZero(outside), 0) << "output outside the mask, frame " << t;
    if (t == 14) {
      EXPECT_EQ(cv::countNonZero(out), 0);
    }
  }
  EXPECT_THROW(filter.apply({cv::Mat(4, 4, CV_8UC3), cv::Mat(4, 4, CV_32FC1), cv::Mat(5, 4, CV_8UC1),
                             cv::Mat(4, 4, CV_32FC2)}),
               Error);
}

}  // namespace
}  // namespace holo::depthfilter
