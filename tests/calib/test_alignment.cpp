// Display alignment, background capture and panorama yaw: known truth in, truth out; bad input
// named; hard cases (NaN depth, all-invalid pixels, mirrored faces) stay bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/calib/background.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/calib/panorama_alignment.hpp"
#include "holo/calib/quality.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "museum_rig.hpp"

namespace holo::calib {
namespace {

std::vector<cv::Point2f> applyAlignment(const FaceAlignment& a, cv::Size view,
                                        const std::vector<cv::Point2f>& dots, double noise,
                                        std::uint64_t seed) {
  const cv::Matx23d A = faceTransform(a, view);
  cv::RNG rng(seed);
  std::vector<cv::Point2f> out;
  for (const auto& p : dots) {
    const cv::Vec2d q = A * cv::Vec3d(p.x, p.y, 1.0);
    out.emplace_back(static_cast<float>(q[0] + rng.gaussian(noise)),
                     static_cast<float>(q[1] + rng.gaussian(noise)));
  }
  return out;
}

TEST(DisplayAlignment, RecoversOffsetScaleRotationAndMirror) {
  const cv::Size view(960, 540);
  const auto dots = testPatternDots(view);
  const FaceAlignment cases[] = {{{0, 0}, 1.0f, 0.0f, false},
                                 {{12.5f, -7.0f}, 0.97f, 3.5f, false},
                                 {{-20.0f, 4.0f}, 1.04f, -90.0f, true},
                                 {{3.0f, 3.0f}, 0.9f, 180.0f, true}};
  for (const FaceAlignment& truth : cases) {
    const FaceFit fit = estimateFaceAlignment(dots, applyAlignment(truth, view, dots, 0.3, 7), view);
    EXPECT_EQ(fit.alignment.mirror, truth.mirror);
    EXPECT_NEAR(fit.alignment.scale, truth.scale, 0.002);
    const double dr = std::remainder(fit.alignment.rotation_deg - truth.rotation_deg, 360.0);
    EXPECT_NEAR(dr, 0.0, 0.1);
    EXPECT_NEAR(fit.alignment.offset_px.x, truth.offset_px.x, 0.3);
    EXPECT_NEAR(fit.alignment.offset_px.y, truth.offset_px.y, 0.3);
    EXPECT_LT(fit.residual_px, 0.6);
    EXPECT_TRUE(judgeDisplay("display", fit.residual_px).pass);
  }
}

TEST(DisplayAlignment, KeystoneFailsWithAHint) {
  const cv::Size view(960, 540);
  const auto dots = testPatternDots(view);
  std::vector<cv::Point2f> keystone;
  for (const auto& p : dots) keystone.emplace_back(p.x + (p.x - 480.0f) * p.y / 540.0f * 0.08f, p.y);
  const FaceFit fit = estimateFaceAlignment(dots, keystone, view);
  const StepVerdict verdict = judgeDisplay("display face 0", fit.residual_px);
  EXPECT_FALSE(verdict.pass) << fit.residual_px;
  EXPECT_NE(verdict.hint.find("scaling"), std::string::npos);
  EXPECT_THROW(estimateFaceAlignment(dots, {{1, 1}}, view), InputError);
  std::vector<cv::Point2f> nan_dots = dots;
  nan_dots[3].x = std::nanf("");
  EXPECT_THROW(estimateFaceAlignment(dots, nan_dots, view), InputError);
  EXPECT_EQ(drawTestPattern(view, 2).size(), view);
}

TEST(Background, MedianRejectsPassersByAndCountsInvalidDepth) {
  const cv::Size size(64, 48);
  std::vector<RgbdFrame> frames;
  cv::RNG rng(3);
  for (int k = 0; k < 15; ++k) {
    RgbdFrame f;
    f.colour = cv::Mat(size, CV_8UC3, cv::Scalar(40, 90, 160));
    f.depth = cv::Mat(size, CV_32FC1, cv::Scalar(2.5f));
    cv::Mat noise(size, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.01);
    f.depth += noise;
    // A visitor crossing in 4 of 15 frames: bright and near.
    if (k < 4) {
      f.colour(cv::Rect(10 + 5 * k, 10, 8, 20)).setTo(cv::Scalar(255, 255, 255));
      f.depth(cv::Rect(10 + 5 * k, 10, 8, 20)).setTo(0.9f);
    }
    // A black, shiny column without depth, NaN and Inf and negative samples sprinkled in.
    f.depth.col(60).setTo(0.0f);
    f.depth.at<float>(5, 5) = std::numeric_limits<float>::quiet_NaN();
    f.depth.at<float>(6, 5) = k % 2 ? std::numeric_limits<float>::infinity() : -1.0f;
    frames.push_back(f);
  }
  const BackgroundModel model = captureBackground(frames);
  EXPECT_EQ(model.frames, 15);
  EXPECT_EQ(model.colour.at<cv::Vec3b>(20, 14), cv::Vec3b(40, 90, 160));
  EXPECT_NEAR(model.depth.at<float>(20, 14), 2.5f, 0.02f);
  EXPECT_EQ(model.depth.at<float>(20, 60), 0.0f);
  EXPECT_EQ(model.invalid_count.at<std::uint16_t>(20, 60), 15);
  EXPECT_EQ(model.depth.at<float>(5, 5), 0.0f);  // NaN in every frame
  EXPECT_EQ(model.invalid_count.at<std::uint16_t>(6, 5), 15);
  EXPECT_EQ(model.invalid_samples, 15 * (48 + 2));
  EXPECT_NEAR(model.invalid_fraction, (48.0 + 2.0) / (64 * 48), 1e-9);
  EXPECT_TRUE(std::isfinite(model.colour_mad));
  EXPECT_TRUE(judgeBackground("background", model.invalid_fraction, model.colour_mad).pass);

  std::vector<RgbdFrame> mismatched = {frames[0], frames[1]};
  mismatched[1].depth = cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f));
  try {
    (void)captureBackground(mismatched, "camera 2");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "frame 1");
  }
  EXPECT_THROW(captureBackground({}), InputError);
}

// A procedural hall panorama with strong, asymmetric structure, seen by a rig camera after the
// panorama was captured turned by a known yaw.
cv::Mat proceduralPanorama() {
  cv::Mat pano(256, 512, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const double u = (x + 0.5) / pano.cols, v = (y + 0.5) / pano.rows;
      const double base =
          0.2 + 0.15 * std::sin(2 * CV_PI * 3 * u) + 0.1 * std::cos(2 * CV_PI * 7 * u + 4 * v);
      const bool window = std::fmod(u * 5.0, 1.0) < 0.3 && v > 0.3 && v < 0.55 && u < 0.7;
      const double radiance = window ? 3.0 + u : base + 0.4 * v;
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(static_cast<float>(radiance * 0.9), static_cast<float>(radiance),
                                           static_cast<float>(radiance * (0.8 + 0.4 * u)));
    }
  return pano;
}

TEST(PanoramaAlignment, RecoversAKnownYaw) {
  const cv::Mat pano = proceduralPanorama();
  const CameraModel camera(test::rigIntrinsics(), toMat4(test::rigCamera(1)));
  for (const float yaw_deg : {0.0f, 37.3f, -123.6f}) {
    const float yaw = yaw_deg * kPi / 180.0f;
    cv::Mat linear(camera.height(), camera.width(), CV_32FC3);
    const std::vector<vec3> table = camera.planeDirectionTable();
    for (int y = 0; y < linear.rows; ++y)
      for (int x = 0; x < linear.cols; ++x) {
        const vec3 d =
            transformDirection(camera.T_world_camera(), table[static_cast<std::size_t>(y * linear.cols + x)]);
        setRgb(linear, x, y, equirect::sample(pano, glm::normalize(d), yaw));
      }
    cv::Mat image = linearToSrgb8(linear, 0.5f);
    cv::Mat noise(image.size(), CV_8UC3);
    cv::randn(noise, cv::Scalar::all(0), cv::Scalar::all(2));
    image += noise;
    const YawFit fit = alignPanoramaYaw(pano, camera, image);
    EXPECT_NEAR(std::remainder(fit.yaw_rad - yaw, 2 * kPi) * 180.0 / kPi, 0.0, 0.1) << yaw_deg;
    EXPECT_GT(fit.correlation, 0.9);
    EXPECT_TRUE(judgePanorama("panorama", fit.correlation).pass);
  }
  EXPECT_THROW(alignPanoramaYaw(cv::Mat(), camera, cv::Mat()), InputError);
}

}  // namespace
}  // namespace holo::calib
