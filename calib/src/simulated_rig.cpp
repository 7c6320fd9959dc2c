#include "holo/calib/simulated_rig.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/pose.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/core/equirect.hpp"

namespace holo::calib {

namespace {
constexpr int kPanoramaWidth = 512;
constexpr int kPanoramaHeight = 256;
}  // namespace

SimulatedRig::SimulatedRig(const std::string& scene, const AutoCalibrationConfig& config)
    : museum_(sim::loadScene(scene)),
      config_(config),
      intrinsics_texture_(renderBoardTexture(config.intrinsics_board, 60)),
      placement_texture_(renderBoardTexture(config.placement_board, 60)) {
  // The panorama was captured turned by 40 of its 512 columns (28.1 degrees); find the yaw
  // that undoes it the way holo::equirect applies a yaw, so the truth has the right sign.
  if (static_cast<int>(config_.placements.size()) != museum_.cameraCount())
    config_.placements = defaultBoardPlacements(config_.placement_board, museum_.cameraCount());
  panorama_shift_px_ = 40;
  const float a = 2.0f * kPi * static_cast<float>(panorama_shift_px_) / kPanoramaWidth;
  const vec3 ahead{0.0f, 0.0f, -1.0f};
  panorama_yaw_ = equirect::directionToUv(ahead, a).x > equirect::directionToUv(ahead, 0.0f).x ? a : -a;
}

int SimulatedRig::cameraCount() const {
  return museum_.cameraCount();
}
std::string SimulatedRig::serial(int camera) const {
  return "sim-" + std::to_string(camera);
}
cv::Size SimulatedRig::imageSize(int camera) const {
  return {museum_.camera(camera).width(), museum_.camera(camera).height()};
}
const CameraModel& SimulatedRig::trueCamera(int camera) const {
  return museum_.camera(camera);
}

cv::Mat SimulatedRig::hallView(int camera) const {
  std::lock_guard lock(cache_mutex_);
  auto& view = hall_views_[camera];
  if (view.empty()) view = museum_.renderCamera(camera, 0, false).frame.colour;
  return view;
}

cv::Mat SimulatedRig::intrinsicsPhoto(int camera, int view) const {
  // The technician holds the board 0.3-0.45 m away, tilted, moving it around the picture.
  // The technician holds the board 0.3-0.45 m away, tilted, and moves it into every part of
  // the wide picture (the corners constrain distortion, which otherwise trades off against the
  // focal length).
  static const double poses[16][6] = {
      {0, 0, 0, 0.0, 0.0, 0.32},         {25, 0, 5, 0.25, 0.08, 0.35},      {-25, 0, -5, -0.25, -0.08, 0.35},
      {0, 30, 10, 0.3, -0.12, 0.38},     {0, -30, -10, -0.3, 0.12, 0.38},   {20, 20, 0, 0.0, 0.15, 0.32},
      {-20, 25, 15, 0.35, 0.0, 0.36},    {20, -25, -15, -0.35, 0.0, 0.36},  {-20, -20, 0, 0.0, -0.15, 0.32},
      {10, -30, 30, 0.3, 0.14, 0.36},    {-30, 10, -20, -0.3, -0.14, 0.36}, {15, 15, 45, 0.3, -0.15, 0.38},
      {-15, -15, -30, -0.3, 0.15, 0.38}, {30, 0, 90, 0.0, 0.0, 0.45},       {0, 35, 0, 0.15, 0.0, 0.3},
      {0, -35, 0, -0.15, 0.0, 0.3}};
  const double* p = poses[view % 16];
  const double d = CV_PI / 180.0;
  cv::Matx33d Rx, Ry, Rz;
  cv::Rodrigues(cv::Vec3d(p[0] * d, 0, 0), Rx);
  cv::Rodrigues(cv::Vec3d(0, p[1] * d, 0), Ry);
  cv::Rodrigues(cv::Vec3d(0, 0, p[2] * d), Rz);
  const cv::Matx33d R = Rx * Ry * Rz;
  const cv::Rect2d e = config_.intrinsics_board.extent();
  const cv::Vec3d t = cv::Vec3d(p[3], p[4], p[5]) - R * cv::Vec3d(e.x + e.width / 2, e.y + e.height / 2, 0);
  const cv::Matx44d T_camera_board(R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1], R(2, 0),
                                   R(2, 1), R(2, 2), t[2], 0, 0, 0, 1);
  SyntheticViewOptions options;
  options.seed = static_cast<std::uint64_t>(1000 + 100 * camera + view);
  cv::Mat photo;
  cv::cvtColor(renderBoardView(intrinsics_texture_, trueCamera(camera).intrinsics(), T_camera_board, options,
                               hallView(camera)),
               photo, cv::COLOR_GRAY2BGR);
  return photo;
}

cv::Mat SimulatedRig::placementPhoto(int camera) const {
  const cv::Matx44d T_camera_board = rigidInverse(toMatx(trueCamera(camera).T_world_camera())) *
                                     config_.placements[static_cast<std::size_t>(camera)];
  SyntheticViewOptions options;
  options.seed = static_cast<std::uint64_t>(2000 + camera);
  options.blur_sigma = 0.5f;
  cv::Mat photo;
  cv::cvtColor(renderBoardView(placement_texture_, trueCamera(camera).intrinsics(), T_camera_board, options,
                               hallView(camera)),
               photo, cv::COLOR_GRAY2BGR);
  return photo;
}

RgbdFrame SimulatedRig::backgroundFrame(int camera, int index) const {
  return museum_.renderCamera(camera, index, false).frame;
}

cv::Mat SimulatedRig::panorama() const {
  const cv::Mat pano = museum_.renderPanorama(kPanoramaWidth, kPanoramaHeight);
  cv::Mat turned(pano.size(), pano.type());
  // Column x of the turned panorama shows what column x - shift showed.
  for (int x = 0; x < pano.cols; ++x)
    pano.col((x - panorama_shift_px_ + pano.cols) % pano.cols).copyTo(turned.col(x));
  return turned;
}

FaceAlignment SimulatedRig::trueFaceAlignment(int face) const {
  // Monitors laid under the pyramid: each face turned a quarter further, the glass mirrors every
  // view, and the installer left a few pixels of offset and a slight scale error.
  return {{3.0f * static_cast<float>(face) - 4.0f, 2.0f - 1.5f * static_cast<float>(face)},
          1.0f - 0.01f * static_cast<float>(face),
          90.0f * static_cast<float>(face) + 0.4f,
          true};
}

std::vector<cv::Point2f> SimulatedRig::observedTestPattern(int face, cv::Size view) const {
  const cv::Matx23d A = faceTransform(trueFaceAlignment(face), view);
  cv::RNG rng(static_cast<std::uint64_t>(3000 + face));
  std::vector<cv::Point2f> observed;
  for (const auto& p : testPatternDots(view)) {
    const cv::Vec2d q = A * cv::Vec3d(p.x, p.y, 1.0);
    observed.emplace_back(static_cast<float>(q[0] + rng.gaussian(0.3)),
                          static_cast<float>(q[1] + rng.gaussian(0.3)));
  }
  return observed;
}

}  // namespace holo::calib
