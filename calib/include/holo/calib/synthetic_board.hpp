// Synthetic photos of a calibration board: the flat board texture seen by a camera with known
// intrinsics (including distortion) at a known pose, anti-aliased, with seeded sensor noise.
// Tests and the simulated wizard run use them as ground truth the calibration must recover.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "holo/calib/board.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::calib {

struct SyntheticViewOptions {
  float noise_sigma = 2.0f;  // Gaussian noise on 8-bit grey levels (0 = none)
  float blur_sigma = 0.0f;   // Gaussian blur in pixels, before noise (motion blur, defocus)
  std::uint64_t seed = 1;
  int supersample = 2;  // rendered at this factor, then area-averaged (anti-aliasing)
};

// Grey CV_8UC1 image of `texture` on the plane Z = 0 of the board frame, seen by a camera with
// intrinsics K placed at T_camera_board (board -> camera, metres). Where the board is not seen
// the pixel is `background` (when given, CV_8UC1 or CV_8UC3 of the image size) or mid grey.
cv::Mat renderBoardView(const BoardTexture& texture, const Intrinsics& K, const cv::Matx44d& T_camera_board,
                        const SyntheticViewOptions& options = {}, const cv::Mat& background = {});

// The board's depth as a depth camera with intrinsics K at T_camera_board sees it: CV_32FC1,
// camera-frame Z in metres where a pixel's ray meets the printed sheet (the texture's extent,
// margin included) from its front, 0 elsewhere; Gaussian noise of `noise_sigma_m` (seeded by
// `seed`) on every board pixel.
cv::Mat renderBoardDepth(const BoardTexture& texture, const Intrinsics& K, const cv::Matx44d& T_camera_board,
                         double noise_sigma_m = 0.0, std::uint64_t seed = 1);

}  // namespace holo::calib
