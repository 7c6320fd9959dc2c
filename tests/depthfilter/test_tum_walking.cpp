// The temporal depth filter on the real Kinect frame with two people (TUM RGB-D fr3/walking_xyz):
// what test_tum_frame.cpp asserts on the office's chair, asserted on people. The people are
// separated from the room by holo::sim::segmentPeople (depth continuity from one seed per person,
// the floor cut off; tests/sim/test_person_segmentation.cpp checks it), and that mask is the
// filter's foreground mask.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/sim/depth_statistics.hpp"
#include "holo/sim/person_segmentation.hpp"
#include "shared_data.hpp"
#include "tum_walking.hpp"

namespace holo::depthfilter {
namespace {

// Synthetic 2x2 holes every 8 px on odd coordinates (see test_tum_frame.cpp for why), where the
// hole's surroundings within edge_radius are measured, on one surface, and on the people.
constexpr int kHoleSpacing = 8;
constexpr int kHoleSize = 2;

struct Hole {
  cv::Rect rect;
  float lo = 0.0f, hi = 0.0f;  // range of the measured depths around it
};

std::vector<Hole> punchableHoles(const cv::Mat& depth, const cv::Mat& people,
                                 const TemporalDepthFilterConfig& config) {
  const int ring = config.edge_radius;
  std::vector<Hole> holes;
  for (int y = ring + 1; y + kHoleSize + ring < depth.rows; y += kHoleSpacing)
    for (int x = ring + 1; x + kHoleSize + ring < depth.cols; x += kHoleSpacing) {
      const cv::Rect around(x - ring - 1, y - ring - 1, kHoleSize + 2 * ring + 2, kHoleSize + 2 * ring + 2);
      const cv::Mat window = depth(around);
      if (cv::countNonZero(window > 0.0f) != window.rows * window.cols) continue;
      if (cv::countNonZero(people(around)) != window.rows * window.cols) continue;
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(window, &lo, &hi);
      if (hi - lo > config.surfaceTolerance(float(lo))) continue;
      holes.push_back({cv::Rect(x, y, kHoleSize, kHoleSize), float(lo), float(hi)});
    }
  return holes;
}

TEST(TemporalDepthFilterTumWalking, FillsHolesOnThePeopleAndNothingElse) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum_walking/depth.png");
  const auto dir = test::sharedData("rgbd/tum_walking");
  const cv::Mat colour = cv::imread((dir / "color.png").string(), cv::IMREAD_COLOR);
  const cv::Mat depth = sim::loadDepthPng((dir / "depth.png").string(), test::kTumDepthUnitsPerMetre);
  ASSERT_EQ(colour.size(), depth.size());
  const cv::Mat people = sim::segmentPeople(depth, test::tumFr3Intrinsics(), test::tumWalkingPersonSeeds());
  ASSERT_GT(cv::countNonZero(people), 50000);  // two people, ~88k of 307k pixels

  const TemporalDepthFilterConfig config;  // the product's defaults
  const std::vector<Hole> holes = punchableHoles(depth, people, config);
  ASSERT_GT(holes.size(), 300u);
  cv::Mat punched = depth.clone();
  for (const Hole& h : holes) punched(h.rect).setTo(0.0f);
  // The sensor's own holes on the people (hair, the shadow inside an arm), which the mask holds.
  const cv::Mat real_holes = (depth <= 0.0f) & people;

  const cv::Mat flow = cv::Mat::zeros(depth.size(), CV_32FC2);  // one frame, repeated: no motion
  const cv::Mat valid = (punched > 0.0f) & people;
  cv::RNG rng(5);
  TemporalDepthFilter filter(config);
  cv::Mat input, output;
  for (int t = 0; t < config.learning_frames + 5; ++t) {
    cv::Mat noise(depth.size(), CV_32FC1), colour_noise(colour.size(), CV_16SC3);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.002);
    rng.fill(colour_noise, cv::RNG::NORMAL, 0.0, 2.0);
    input = punched + noise;
    input.setTo(0.0f, punched == 0.0f);
    cv::Mat noisy_colour;
    cv::add(colour, colour_noise, noisy_colour, cv::noArray(), CV_8UC3);
    output = filter.apply({noisy_colour, input, people, flow});
  }
  ASSERT_FALSE(filter.learning());

  long filled = 0, plausible = 0, hole_pixels = 0;
  for (const Hole& h : holes)
    for (int y = h.rect.y; y < h.rect.br().y; ++y)
      for (int x = h.rect.x; x < h.rect.br().x; ++x) {
        const float d = output.at<float>(y, x);
        ++hole_pixels;
        if (!(d > 0.0f && std::isfinite(d))) continue;
        ++filled;
        plausible += d >= h.lo - 0.006f && d <= h.hi + 0.006f;  // 3 sigma of the 2 mm noise
      }
  // A filled real hole lies within the range of the measured depths within fill_radius of it.
  long real_filled = 0, real_within = 0;
  const int r = config.fill_radius;
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      if (!real_holes.at<std::uint8_t>(y, x) || !(output.at<float>(y, x) > 0.0f)) continue;
      ++real_filled;
      const cv::Rect around =
          cv::Rect(x - r, y - r, 2 * r + 1, 2 * r + 1) & cv::Rect(0, 0, depth.cols, depth.rows);
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(depth(around), &lo, &hi, nullptr, nullptr, depth(around) > 0.0f);
      real_within += output.at<float>(y, x) >= lo - 0.006f && output.at<float>(y, x) <= hi + 0.006f;
    }

  cv::Mat moved;
  cv::absdiff(output, input, moved);
  const double mean_move_m = cv::mean(moved, valid & (output > 0.0f))[0];
  const double kept = double(cv::countNonZero(valid & (output > 0.0f))) / double(cv::countNonZero(valid));
  const cv::Mat outside = (output != 0.0f) & ~people;
  const double fill = double(filled) / double(hole_pixels);
  std::printf(
      "people %d px; synthetic holes %zu (%ld px): filled %.4f, plausible %ld/%ld; real holes on the people "
      "%d px, filled %ld, within their neighbours' range %ld; valid depth kept %.4f, mean move %.3f mm\n",
      cv::countNonZero(people), holes.size(), hole_pixels, fill, plausible, filled,
      cv::countNonZero(real_holes), real_filled, real_within, kept, 1000.0 * mean_move_m);
  EXPECT_GT(fill, 0.95);
  EXPECT_EQ(plausible, filled);
  EXPECT_EQ(real_within, real_filled);
  EXPECT_GT(kept, 0.97);
  EXPECT_LT(mean_move_m, 0.005);
  EXPECT_EQ(cv::countNonZero(outside), 0);
  EXPECT_EQ(cv::countNonZero(output != output), 0);  // no NaN
}

}  // namespace
}  // namespace holo::depthfilter
