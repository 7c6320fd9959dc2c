#include "holo/reflect/foreground_pyramid.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::reflect {
namespace {

// The blur a read delivers, measured on an impulse: the variance of the response along x.
TEST(ForegroundPyramid, MeasuredBlurMatchesTheDerivedSigma) {
  cv::Mat colour(256, 256, CV_32FC3, cv::Scalar::all(0));
  cv::Mat mask(256, 256, CV_32FC1, cv::Scalar(0));
  colour.at<cv::Vec3f>(128, 128) = cv::Vec3f(1, 1, 1);
  mask.at<float>(128, 128) = 1.0f;
  const ForegroundPyramid pyramid(colour, mask, 6);
  for (int level = 1; level < 6; ++level) {
    double sum = 0.0, mean = 0.0, sq = 0.0;
    for (int x = 0; x < 256; ++x) {
      const double w = pyramid.sample(vec2(float(x), 128.0f), float(level)).weight;
      sum += w;
      mean += w * x;
      sq += w * double(x) * x;
    }
    mean /= sum;
    const double sigma = std::sqrt(sq / sum - mean * mean);
    EXPECT_NEAR(sigma, pyramidSigmaPx(float(level)), 0.2 * pyramidSigmaPx(float(level))) << "level " << level;
    EXPECT_NEAR(pyramidLevelForSigma(pyramidSigmaPx(float(level))), float(level), 1e-3f);
  }
}

TEST(ForegroundPyramid, PremultipliedBlurKeepsForegroundColourAndWeightsItsCoverage) {
  // A red foreground disc on a bright green background: the background must not bleed in.
  cv::Mat colour(128, 128, CV_32FC3, cv::Scalar(0, 5, 0));
  cv::Mat mask(128, 128, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if ((x - 64) * (x - 64) + (y - 64) * (y - 64) < 30 * 30) {
        colour.at<cv::Vec3f>(y, x) = cv::Vec3f(0, 0, 2);
        mask.at<std::uint8_t>(y, x) = 255;
      }
  const ForegroundPyramid pyramid(colour, mask, 5);
  for (float level : {0.0f, 2.5f, 4.0f}) {
    const ForegroundSample edge = pyramid.sample(vec2(64.0f + 29.5f, 64.0f), level);
    EXPECT_GT(edge.weight, 0.1f);
    EXPECT_LT(edge.weight, 0.9f);
    EXPECT_NEAR(edge.radiance.r, 2.0f, 1e-3f);
    EXPECT_NEAR(edge.radiance.g, 0.0f, 1e-3f);
    const ForegroundSample centre = pyramid.sample(vec2(64.0f), level);
    EXPECT_GT(centre.weight, 0.9f);
  }
  EXPECT_EQ(pyramid.sample(vec2(2.0f), 0.0f).weight, 0.0f);
  EXPECT_EQ(pyramid.sample(vec2(2.0f), 0.0f).radiance, vec3(0.0f));
}

TEST(ForegroundPyramid, NonFiniteInputsAreRepairedAndReadsStayBounded) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat colour(16, 16, CV_32FC3, cv::Scalar(nan, inf, 1));
  cv::Mat mask(16, 16, CV_32FC1, cv::Scalar(nan));
  mask.at<float>(3, 3) = inf;
  mask.at<float>(4, 4) = 7.0f;
  const ForegroundPyramid pyramid(colour, mask, 3);
  for (float level : {-5.0f, 0.0f, 1.5f, 99.0f, nan})
    for (const vec2 p : {vec2(4.0f), vec2(-100.0f), vec2(nan, 0.0f), vec2(1e30f)}) {
      const ForegroundSample s = pyramid.sample(p, level);
      EXPECT_TRUE(isFinite(s.radiance));
      EXPECT_GE(s.weight, 0.0f);
      EXPECT_LE(s.weight, 1.0f);
    }
  EXPECT_NEAR(pyramid.sample(vec2(4.0f), 0.0f).weight, 1.0f, 1e-6f);
}

// The full-image build the support-restricted one must equal: repair, premultiply, then every
// level the 4x4 Kawase kernel over the whole previous level (edges replicated), even pixels kept.
std::vector<std::pair<cv::Mat, cv::Mat>> fullImagePyramid(const cv::Mat& colour_bgr, const cv::Mat& mask,
                                                          int levels) {
  cv::Mat m, c = colour_bgr.clone();
  if (mask.type() == CV_8UC1)
    mask.convertTo(m, CV_32F, 1.0 / 255.0);
  else
    m = mask.clone();
  cv::patchNaNs(m, 0.0);
  cv::min(cv::max(m, 0.0), 1.0, m);
  c.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k]) || p[k] < 0.0f) p[k] = 0.0f;
  });
  cv::Mat m3;
  cv::merge(std::vector<cv::Mat>{m, m, m}, m3);
  std::vector<std::pair<cv::Mat, cv::Mat>> out{{c.mul(m3), m}};
  const cv::Mat kernel = (cv::Mat_<float>(4, 4) << 1, 1, 1, 1, 1, 5, 5, 1, 1, 5, 5, 1, 1, 1, 1, 1) / 32.0f;
  auto down = [&](const cv::Mat& in) {
    cv::Mat filtered;
    cv::filter2D(in, filtered, -1, kernel, cv::Point(1, 1), 0.0, cv::BORDER_REPLICATE);
    cv::Mat half(std::max(1, (in.rows + 1) / 2), std::max(1, (in.cols + 1) / 2), in.type());
    for (int y = 0; y < half.rows; ++y)
      for (int x = 0; x < half.cols; ++x)
        std::memcpy(half.ptr(y, x), filtered.ptr(2 * y, 2 * x), in.elemSize());
    return half;
  };
  for (int l = 1; l < levels; ++l) out.emplace_back(down(out.back().first), down(out.back().second));
  return out;
}

// Largest absolute difference, relative to the reference's largest value (1 when all zero).
double relativeDifference(const cv::Mat& a, const cv::Mat& b) {
  double peak = 0.0;
  cv::minMaxLoc(b.reshape(1), nullptr, &peak);
  return cv::norm(a, b, cv::NORM_INF) / std::max(peak, 1e-30);
}

TEST(ForegroundPyramid, SupportRestrictedBuildEqualsTheFullImageBuild) {
  const int w = 203, h = 117, levels = 7;  // odd sizes: every level halves with a remainder
  cv::RNG rng(7);
  cv::Mat colour(h, w, CV_32FC3);
  rng.fill(colour, cv::RNG::UNIFORM, 0.0, 4.0);
  colour.at<cv::Vec3f>(5, 5) =
      cv::Vec3f(std::numeric_limits<float>::quiet_NaN(), 1, 1);  // outside most masks
  auto disc = [&](int cx, int cy, int r) {
    cv::Mat m(h, w, CV_32FC1, cv::Scalar(0));
    cv::circle(m, cv::Point(cx, cy), r, cv::Scalar(0.8), cv::FILLED);
    return m;
  };
  cv::Mat soft = disc(150, 60, 20);
  cv::GaussianBlur(soft, soft, cv::Size(9, 9), 3.0);
  cv::Mat corner(h, w, CV_8UC1, cv::Scalar(0));
  corner(cv::Rect(w - 9, h - 6, 9, 6)).setTo(200);  // touching the right and bottom borders
  cv::Mat tiny(h, w, CV_32FC1, cv::Scalar(0));
  tiny.at<float>(40, 77) = 1.0f;
  const std::vector<std::pair<const char*, cv::Mat>> masks{
      {"empty", cv::Mat(h, w, CV_32FC1, cv::Scalar(0))},
      {"full", cv::Mat(h, w, CV_32FC1, cv::Scalar(1))},
      {"disc", disc(60, 50, 25)},
      {"soft disc", soft},
      {"top-left border", disc(0, 0, 12)},
      {"bottom-right border (8-bit)", corner},
      {"tiny", tiny},
  };
  // One pyramid rebuilt for every mask in turn: the previous mask's support must be cleared.
  ForegroundPyramid pyramid;
  for (const auto& [name, mask] : masks) {
    pyramid.build(colour, mask, levels);
    const auto reference = fullImagePyramid(colour, mask, levels);
    ASSERT_EQ(pyramid.levels(), levels);
    for (int l = 0; l < levels; ++l) {
      const auto& [ref_colour, ref_mask] = reference[std::size_t(l)];
      ASSERT_EQ(pyramid.premultipliedColour(l).size(), ref_colour.size()) << name << " level " << l;
      EXPECT_LE(relativeDifference(pyramid.premultipliedColour(l), ref_colour), 1e-6)
          << name << " level " << l;
      EXPECT_LE(relativeDifference(pyramid.mask(l), ref_mask), 1e-6) << name << " level " << l;
      // The support is exactly the box of the reference's non-zero pixels (the kernel is positive
      // everywhere, so every pixel whose footprint meets the mask is non-zero).
      EXPECT_EQ(pyramid.support(l), cv::boundingRect(ref_mask > 0.0f)) << name << " level " << l;
    }
  }
  // The last mask was one pixel: level 0 is that pixel; a step maps a width w to at most
  // w / 2 + 2, so the box stays within 3x3 pixels at every level.
  EXPECT_EQ(pyramid.support(0), cv::Rect(77, 40, 1, 1));
  for (int l = 0; l < levels; ++l) EXPECT_LE(pyramid.support(l).area(), 9) << "level " << l;
  pyramid.build(colour, masks.front().second, levels);  // empty mask: nothing to filter
  EXPECT_TRUE(pyramid.support(0).empty());
  EXPECT_TRUE(pyramid.support(levels - 1).empty());
  pyramid.clear();
  EXPECT_TRUE(pyramid.empty());
  EXPECT_EQ(pyramid.sample(vec2(77.0f, 40.0f), 0.0f).weight, 0.0f);
}

TEST(ForegroundPyramid, RejectsMismatchedInputs) {
  const cv::Mat colour(8, 8, CV_32FC3, cv::Scalar::all(0));
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 9, CV_32FC1), 2), InputError);
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 8, CV_16UC1), 2), InputError);
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 8, CV_32FC1), 0), InputError);
  EXPECT_THROW(ForegroundPyramid(cv::Mat(8, 8, CV_8UC3), cv::Mat(8, 8, CV_32FC1), 2), InputError);
}

TEST(ForegroundLevel, GrowsWithRoughnessAndTravelAndStaysInRange) {
  EXPECT_EQ(foregroundLevel(0.0f, 1.0f, 1.0f, 600.0f, 6), 0.0f);  // a mirror reads level 0
  float previous = 0.0f;
  for (float r : {0.1f, 0.2f, 0.4f, 0.7f, 1.0f}) {
    const float l = foregroundLevel(r, 0.5f, 1.5f, 600.0f, 8);
    EXPECT_GE(l, previous);
    previous = l;
  }
  EXPECT_GT(previous, 5.0f);
  EXPECT_LT(foregroundLevel(0.3f, 0.2f, 1.5f, 600.0f, 8), foregroundLevel(0.3f, 0.8f, 1.5f, 600.0f, 8));
  // Roughness 0.3: alpha 0.09, lobe sqrt(2) 0.09 rad; 0.5 m travel seen from 1.5 m at f = 600 px
  // spreads sigma = 0.5 tan(0.127) 600 / 1.5 = 25.6 px -> L = log2((25.6^2 + 0.25) 2.4) / 2.
  const float sigma = 0.5f * std::tan(std::sqrt(2.0f) * 0.09f) * 600.0f / 1.5f;
  EXPECT_NEAR(foregroundLevel(0.3f, 0.5f, 1.5f, 600.0f, 12), 0.5f * std::log2((sigma * sigma + 0.25f) * 2.4f),
              1e-4f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(foregroundLevel(nan, nan, 1.0f, 600.0f, 6), 0.0f);
  EXPECT_EQ(foregroundLevel(1.0f, 1e30f, 1e-30f, 600.0f, 6), 5.0f);  // overflow: the top level
  EXPECT_LE(foregroundLevel(1.0f, 100.0f, 0.01f, 600.0f, 6), 5.0f);
}

// GGX slopes (in units of alpha) are exceeded in length r with probability 1 / (1 + r^2); a
// Gaussian mixture's slopes with probability sum_k w_k exp(-r^2 g_k / 2), g_k = 2 / scale_k^2.
TEST(GgxLobeMixture, FollowsTheGgxLobesHeavyTail) {
  const auto tail = [](const std::vector<LobeComponent>& mixture, double r) {
    double p = 0.0, weights = 0.0;
    for (const LobeComponent& c : mixture) {
      const double g = 2.0 / (double(c.sigma_scale) * double(c.sigma_scale));
      p += c.weight * std::exp(-r * r * g / 2.0);
      weights += c.weight;
    }
    EXPECT_NEAR(weights, 1.0, 1e-6);
    return p;
  };
  const auto ggx = [](double r) { return 1.0 / (1.0 + r * r); };
  const std::vector<LobeComponent> single = ggxLobeMixture(1);
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].sigma_scale, 1.0f);  // reflectedLobeSigma itself
  // One Gaussian loses the tail: 2 alpha out it holds 2% of the slopes where GGX holds 20%.
  EXPECT_LT(tail(single, 2.0), 0.1 * ggx(2.0));
  for (const int n : {2, 4, 8}) {
    const std::vector<LobeComponent> mixture = ggxLobeMixture(n);
    ASSERT_EQ(mixture.size(), std::size_t(n));
    for (std::size_t k = 1; k < mixture.size(); ++k)
      EXPECT_LT(mixture[k].sigma_scale, mixture[k - 1].sigma_scale);
    for (const double r : {0.5, 1.0, 2.0})
      EXPECT_NEAR(tail(mixture, r), ggx(r), 0.25 * ggx(r)) << n << " " << r;
  }
  EXPECT_NEAR(tail(ggxLobeMixture(8), 4.0), ggx(4.0), 0.25 * ggx(4.0));
  EXPECT_THROW(ggxLobeMixture(0), InputError);
  EXPECT_THROW(ggxLobeMixture(kMaxLobeComponents + 1), InputError);
}

}  // namespace
}  // namespace holo::reflect
