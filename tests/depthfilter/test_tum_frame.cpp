// The temporal depth filter on a real Kinect frame (TUM RGB-D, an office scene): the synthetic
// scenes elsewhere have ideal depth; this checks the fill and the fidelity on real sensor depth
// with its quantization steps and real surface shape.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "shared_data.hpp"

namespace holo::depthfilter {
namespace {

constexpr double kTumDepthScale = 5000.0;  // TUM depth PNG units per metre

// The backrest of the red office chair at the bottom left, 1.5-1.9 m away, well in front of the
// floor (2.3-3.3 m): one real, slanted object, kept inside its outline so that the mask covers
// the object and not the floor beside it.
const cv::Rect kChair{70, 296, 65, 100};

// The backrest has no sensor holes of its own, so the test punches synthetic 2x2 holes every
// 8 px into it. Each starts on odd coordinates so that it straddles four 2x2 pull blocks and
// each of its pixels has a parent block that keeps a measurement. A hole aligned to a block
// (even x and y) empties the whole block, which is beyond the reach of the default l_max = 2
// (measured: none of its pixels filled); that is the documented limit, not what this checks.
constexpr int kHoleSpacing = 8;
constexpr int kHoleSize = 2;

struct Hole {
  cv::Rect rect;
  float lo = 0.0f, hi = 0.0f;  // range of the noise-free measured depths around it
};

// Holes whose surroundings within edge_radius span more than the same-surface tolerance sit on a
// depth edge, and holes within edge_radius of the mask's edge may continue an unmeasured surface
// (a silhouette); without a measured precursor both stay holes on purpose. They are not punched,
// so only the fill is measured.
std::vector<Hole> punchableHoles(const cv::Mat& depth, const TemporalDepthFilterConfig& config) {
  const int ring = config.edge_radius;
  std::vector<Hole> holes;
  for (int y = kChair.y + ring + 1; y + kHoleSize + ring < kChair.br().y; y += kHoleSpacing)
    for (int x = kChair.x + ring + 1; x + kHoleSize + ring < kChair.br().x; x += kHoleSpacing) {
      const cv::Rect around(x - ring, y - ring, kHoleSize + 2 * ring, kHoleSize + 2 * ring);
      const cv::Mat window = depth(around);
      if (cv::countNonZero(window > 0.0f) != window.rows * window.cols) continue;
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(window, &lo, &hi);
      if (hi - lo > config.surfaceTolerance(float(lo))) continue;
      holes.push_back({cv::Rect(x, y, kHoleSize, kHoleSize), float(lo), float(hi)});
    }
  return holes;
}

TEST(TemporalDepthFilterTum, FillsHolesInsideTheMaskAndKeepsValidDepth) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum/depth.png");
  const auto dir = test::sharedData("rgbd/tum");
  const cv::Mat colour = cv::imread((dir / "color.png").string(), cv::IMREAD_COLOR);
  const cv::Mat raw = cv::imread((dir / "depth.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  ASSERT_EQ(colour.size(), raw.size());
  cv::Mat depth;
  raw.convertTo(depth, CV_32FC1, 1.0 / kTumDepthScale);

  const TemporalDepthFilterConfig config;  // the product's defaults
  const std::vector<Hole> holes = punchableHoles(depth, config);
  ASSERT_GT(holes.size(), 30u);
  cv::Mat punched = depth.clone();
  for (const Hole& h : holes) punched(h.rect).setTo(0.0f);

  cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8UC1);
  mask(kChair).setTo(255);
  const cv::Mat flow = cv::Mat::zeros(depth.size(), CV_32FC2);  // the camera is still
  const cv::Mat valid = (punched > 0.0f) & mask;

  // Per-frame sensor noise on depth (2 mm) and colour (2 levels) keeps the learned PDFs of |d|
  // and alpha from collapsing to a single value, as they would on a frame repeated exactly.
  cv::RNG rng(3);
  TemporalDepthFilter filter(config);
  cv::Mat input, output;
  const int frames = config.learning_frames + 5;
  for (int t = 0; t < frames; ++t) {
    cv::Mat noise(depth.size(), CV_32FC1), colour_noise(colour.size(), CV_16SC3);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.002);
    rng.fill(colour_noise, cv::RNG::NORMAL, 0.0, 2.0);
    input = punched + noise;
    input.setTo(0.0f, punched == 0.0f);
    cv::Mat noisy_colour;
    cv::add(colour, colour_noise, noisy_colour, cv::noArray(), CV_8UC3);
    output = filter.apply({noisy_colour, input, mask, flow});
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
        // 3 sigma of the depth noise beyond the noise-free range around the hole.
        plausible += d >= h.lo - 0.006f && d <= h.hi + 0.006f;
      }

  cv::Mat moved;
  cv::absdiff(output, input, moved);
  const double mean_move_m = cv::mean(moved, valid)[0];
  const cv::Mat outside = (output != 0.0f) & ~mask;

  const double fill = double(filled) / double(hole_pixels);
  std::printf(
      "synthetic holes %zu (%ld px): filled %.4f, plausible %ld/%ld; mean move of valid depth %.3f mm\n",
      holes.size(), hole_pixels, fill, plausible, filled, 1000.0 * mean_move_m);
  EXPECT_GT(fill, 0.97);  // measured 0.9947 (374 of 376 pixels)
  EXPECT_EQ(plausible, filled);
  EXPECT_LT(mean_move_m, 0.01);
  EXPECT_EQ(cv::countNonZero(outside), 0);
  EXPECT_EQ(cv::countNonZero(output != output), 0);  // no NaN
}

}  // namespace
}  // namespace holo::depthfilter
