#include "holo/calib/synthetic_board.hpp"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace holo::calib {

cv::Mat renderBoardView(const BoardTexture& texture, const Intrinsics& K, const cv::Matx44d& T_camera_board,
                        const SyntheticViewOptions& options, const cv::Mat& background) {
  const int s = std::max(1, options.supersample);
  const cv::Size size(K.width, K.height), big(K.width * s, K.height * s);
  // Pixel u of the final image covers supersampled pixels s*u .. s*u + s-1, centred at
  // s*u + (s-1)/2, so the supersampled principal point shifts by (s-1)/2.
  const double shift = 0.5 * (s - 1);
  const cv::Matx33d K_big(K.fx * s, 0, K.cx * s + shift, 0, K.fy * s, K.cy * s + shift, 0, 0, 1);
  // Board plane to (undistorted) image: K [r1 r2 t].
  const cv::Matx33d Rt(T_camera_board(0, 0), T_camera_board(0, 1), T_camera_board(0, 3), T_camera_board(1, 0),
                       T_camera_board(1, 1), T_camera_board(1, 3), T_camera_board(2, 0), T_camera_board(2, 1),
                       T_camera_board(2, 3));
  const cv::Matx33d board_to_image = K_big * Rt;
  const cv::Matx33d texture_to_image = board_to_image * texture.board_to_pixel.inv();

  // Warp into an undistorted image with a validity mask (which pixels see the board's front).
  cv::Mat undistorted, mask;
  cv::warpPerspective(texture.image, undistorted, texture_to_image, big, cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::warpPerspective(cv::Mat(texture.image.size(), CV_8UC1, cv::Scalar(255)), mask, texture_to_image, big,
                      cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  // The printed side faces board -Z: the camera sees it only from that side of the plane
  // (origin . normal > 0 in camera coordinates); from behind, the board stays empty.
  const cv::Vec3d normal_cam(T_camera_board(0, 2), T_camera_board(1, 2), T_camera_board(2, 2));
  const cv::Vec3d origin_cam(T_camera_board(0, 3), T_camera_board(1, 3), T_camera_board(2, 3));
  if (origin_cam.dot(normal_cam) <= 0) mask.setTo(0);  // the camera sees the board's back

  cv::Mat big_background;
  if (!background.empty()) {
    cv::Mat grey = background;
    if (grey.channels() == 3) cv::cvtColor(background, grey, cv::COLOR_BGR2GRAY);
    cv::resize(grey, big_background, big, 0, 0, cv::INTER_NEAREST);
  } else {
    big_background = cv::Mat(big, CV_8UC1, cv::Scalar(128));
  }
  cv::Mat composed(big, CV_8UC1);
  for (int y = 0; y < big.height; ++y)
    for (int x = 0; x < big.width; ++x) {
      const int a = mask.at<std::uint8_t>(y, x);
      composed.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(
          (undistorted.at<std::uint8_t>(y, x) * a + big_background.at<std::uint8_t>(y, x) * (255 - a) + 127) /
          255);
    }

  // Lens distortion: each distorted output pixel samples the undistorted image where
  // undistortPoints sends it. Distortion is smooth, so the map is computed on a grid every
  // kStep pixels and interpolated (a 16x saving; the interpolation error is far below 0.01 px).
  if (K.hasDistortion()) {
    constexpr int kStep = 4;
    const int gw = big.width / kStep + 2, gh = big.height / kStep + 2;
    std::vector<cv::Point2f> nodes;
    nodes.reserve(static_cast<std::size_t>(gw * gh));
    for (int gy = 0; gy < gh; ++gy)
      for (int gx = 0; gx < gw; ++gx)
        nodes.emplace_back(static_cast<float>(gx * kStep), static_cast<float>(gy * kStep));
    std::vector<cv::Point2f> sources;
    const cv::Vec<double, 5> dist(K.distortion[0], K.distortion[1], K.distortion[2], K.distortion[3],
                                  K.distortion[4]);
    cv::undistortPoints(nodes, sources, K_big, dist, cv::noArray(), K_big,
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-8));
    const cv::Mat coarse(gh, gw, CV_32FC2, sources.data());
    cv::Mat grid_x(big, CV_32FC1), grid_y(big, CV_32FC1);
    for (int y = 0; y < big.height; ++y)
      for (int x = 0; x < big.width; ++x) {
        grid_x.at<float>(y, x) = static_cast<float>(x) / kStep;
        grid_y.at<float>(y, x) = static_cast<float>(y) / kStep;
      }
    cv::Mat map, distorted;
    cv::remap(coarse, map, grid_x, grid_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    cv::remap(composed, distorted, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    composed = distorted;
  }

  cv::Mat image;
  if (s > 1)
    cv::resize(composed, image, size, 0, 0, cv::INTER_AREA);
  else
    image = composed;
  if (options.blur_sigma > 0) cv::GaussianBlur(image, image, cv::Size(), options.blur_sigma);
  if (options.noise_sigma > 0) {
    cv::Mat noise(size, CV_32FC1);
    cv::RNG rng(options.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    cv::Mat f;
    image.convertTo(f, CV_32F);
    f += noise;
    f.convertTo(image, CV_8U);  // saturates
  }
  return image;
}

cv::Mat renderBoardDepth(const BoardTexture& texture, const Intrinsics& K, const cv::Matx44d& T_camera_board,
                         double noise_sigma_m, std::uint64_t seed) {
  const cv::Size size(K.width, K.height);
  cv::Mat depth = cv::Mat::zeros(size, CV_32FC1);
  const cv::Vec3d normal(T_camera_board(0, 2), T_camera_board(1, 2), T_camera_board(2, 2));
  const cv::Vec3d origin(T_camera_board(0, 3), T_camera_board(1, 3), T_camera_board(2, 3));
  const double offset = origin.dot(normal);
  if (offset <= 0) return depth;  // the board's back faces the camera
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<std::size_t>(size.area()));
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) pixels.emplace_back(static_cast<float>(x), static_cast<float>(y));
  std::vector<cv::Point2f> rays;
  const cv::Matx33d Kmat(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  const cv::Vec<double, 5> dist(K.distortion[0], K.distortion[1], K.distortion[2], K.distortion[3],
                                K.distortion[4]);
  cv::undistortPoints(pixels, rays, Kmat, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-8));
  const cv::Matx33d R_board_camera(T_camera_board(0, 0), T_camera_board(1, 0), T_camera_board(2, 0),
                                   T_camera_board(0, 1), T_camera_board(1, 1), T_camera_board(2, 1),
                                   T_camera_board(0, 2), T_camera_board(1, 2), T_camera_board(2, 2));
  cv::RNG rng(seed);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const cv::Point2f& r = rays[static_cast<std::size_t>(y * size.width + x)];
      const cv::Vec3d ray(r.x, r.y, 1.0);
      const double along = normal.dot(ray);
      if (along <= 1e-9) continue;
      const double z = offset / along;  // the ray's z is 1, so its parameter is the depth
      const cv::Vec3d on_board = R_board_camera * (z * ray - origin);
      const cv::Vec3d texel = texture.board_to_pixel * cv::Vec3d(on_board[0], on_board[1], 1.0);
      if (texel[0] < -0.5 || texel[1] < -0.5 || texel[0] > texture.image.cols - 0.5 ||
          texel[1] > texture.image.rows - 0.5)
        continue;
      depth.at<float>(y, x) = static_cast<float>(z + (noise_sigma_m > 0 ? rng.gaussian(noise_sigma_m) : 0.0));
    }
  return depth;
}

}  // namespace holo::calib
