// A synthetic RGBD sequence with known truth for the depth filter's and its evaluation's tests: a
// textured background plane at 3 m, a static textured box at 2 m (the "visitor who stands still")
// and a textured dome-shaped disc at about 1.5 m that moves sideways. Depth gets Gaussian noise
// growing with z^2, random dropouts and a persistent hole inside the box; colour gets Gaussian
// noise. Seeded.
#pragma once

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::test {

struct SyntheticFrame {
  RgbdFrame frame;
  cv::Mat true_depth;  // CV_32FC1 metres, noise-free, no holes
  cv::Mat true_mask;   // CV_8UC1, 255 on the box and the disc
  cv::Mat disc_mask;   // CV_8UC1, 255 on the moving disc only
  cv::Mat box_mask;    // CV_8UC1, 255 on the static box only
};

struct SyntheticScene {
  int width = 320;
  int height = 180;
  float focal = 250.0f;
  float background_z = 3.0f;
  float box_z = 2.0f;
  cv::Rect box{40, 50, 60, 80};
  float disc_z = 1.5f;  // rim depth; the centre bulges `disc_bulge` towards the camera
  float disc_bulge = 0.08f;
  float disc_radius_px = 28.0f;
  float disc_speed_px = 2.0f;  // per frame, to the right
  float sigma_0 = 0.002f;      // depth noise sigma(z) = sigma_0 + k_z2 z^2
  float k_z2 = 0.0025f;
  double dropout = 0.03;  // random depth holes
  double colour_sigma = 2.0;
  bool objects = true;
  // A background colour match: the box takes exactly the background's colours (depth only).
  bool box_matches_background = false;
  float brightness_offset = 0.0f;  // added to every colour channel (a sudden lighting change)

  Intrinsics intrinsics() const {
    Intrinsics K;
    K.width = width;
    K.height = height;
    K.fx = K.fy = focal;
    K.cx = float(width - 1) / 2.0f;
    K.cy = float(height - 1) / 2.0f;
    return K;
  }

  cv::Point2f discCentre(int t) const { return {110.0f + disc_speed_px * float(t), 95.0f}; }

  static cv::Vec3b backgroundColour(int x, int y) {
    // Large-scale texture so optical flow and MOG2 have structure to work with.
    const int cell = ((x / 12) * 7 + (y / 12) * 13) % 5;
    return cv::Vec3b(static_cast<std::uint8_t>(60 + 30 * cell), static_cast<std::uint8_t>(90 + 15 * cell),
                     static_cast<std::uint8_t>(140 - 20 * cell));
  }

  SyntheticFrame render(int t, std::uint64_t seed) const {
    SyntheticFrame out;
    cv::Mat colour(height, width, CV_8UC3);
    out.true_depth = cv::Mat(height, width, CV_32FC1, cv::Scalar(background_z));
    out.true_mask = cv::Mat::zeros(height, width, CV_8UC1);
    out.disc_mask = cv::Mat::zeros(height, width, CV_8UC1);
    out.box_mask = cv::Mat::zeros(height, width, CV_8UC1);
    const cv::Point2f c = discCentre(t);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        colour.at<cv::Vec3b>(y, x) = backgroundColour(x, y);
        if (!objects) continue;
        if (box.contains({x, y})) {
          out.true_depth.at<float>(y, x) = box_z;
          out.true_mask.at<std::uint8_t>(y, x) = out.box_mask.at<std::uint8_t>(y, x) = 255;
          if (!box_matches_background)
            colour.at<cv::Vec3b>(y, x) =
                ((x / 6 + y / 6) % 2) ? cv::Vec3b(30, 200, 40) : cv::Vec3b(20, 120, 220);
        }
        const float dx = float(x) - c.x, dy = float(y) - c.y;
        const float r2 = (dx * dx + dy * dy) / (disc_radius_px * disc_radius_px);
        if (r2 <= 1.0f) {
          out.true_depth.at<float>(y, x) = disc_z - disc_bulge * std::sqrt(1.0f - r2);
          out.true_mask.at<std::uint8_t>(y, x) = out.disc_mask.at<std::uint8_t>(y, x) = 255;
          out.box_mask.at<std::uint8_t>(y, x) = 0;  // the disc passes in front of the box
          // Texture attached to the disc (moves with it): stripes and a radial ramp.
          const int stripe = (int(std::floor(dx / 5.0f)) + int(std::floor(dy / 7.0f))) & 1;
          colour.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<std::uint8_t>(stripe ? 220 : 40),
                                                 static_cast<std::uint8_t>(60 + 150 * r2),
                                                 static_cast<std::uint8_t>(stripe ? 30 : 200));
        }
      }
    cv::RNG rng(seed * 7919u + std::uint64_t(t) * 104729u + 17u);
    cv::Mat colour_noise(height, width, CV_32FC3);
    rng.fill(colour_noise, cv::RNG::NORMAL, cv::Scalar::all(brightness_offset),
             cv::Scalar::all(colour_sigma));
    cv::Mat colour_f;
    colour.convertTo(colour_f, CV_32FC3);
    colour_f += colour_noise;
    colour_f.convertTo(out.frame.colour, CV_8UC3);  // saturating

    out.frame.depth = out.true_depth.clone();
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        float& d = out.frame.depth.at<float>(y, x);
        d += float(rng.gaussian(sigma_0 + k_z2 * d * d));
        if (rng.uniform(0.0, 1.0) < dropout) d = 0.0f;
      }
    // A persistent hole (a dark, absorbing patch) inside the box.
    if (objects) out.frame.depth(cv::Rect(box.x + 20, box.y + 30, 12, 10)).setTo(0.0f);
    out.frame.camera_id = 0;
    out.frame.sequence = static_cast<std::uint64_t>(t);
    return out;
  }
};

}  // namespace holo::test
