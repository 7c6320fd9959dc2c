#include "holo/simulated/simulated_rig.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/pose.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/calib/verification_target.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/image.hpp"

namespace holo::simulated {

using calib::AutoCalibrationConfig;
using calib::BoardSpec;
using calib::BoardTexture;
using calib::FaceAlignment;
using calib::RigActivity;
using calib::SyntheticViewOptions;

namespace {
constexpr int kPanoramaWidth = 512;
constexpr int kPanoramaHeight = 256;
}  // namespace

SimulatedRig::SimulatedRig(const std::string& scene, const AutoCalibrationConfig& config)
    : SimulatedRig(sim::loadScene(scene), config) {}

SimulatedRig::SimulatedRig(sim::SceneDescription scene, const AutoCalibrationConfig& config)
    : museum_(scene),
      scene_(scene.name),
      config_(config),
      intrinsics_texture_(calib::renderBoardTexture(config.intrinsics_board, 60)),
      placement_texture_(calib::renderBoardTexture(config.placement_board, 60)),
      verification_texture_(calib::renderVerificationTargetTexture()) {
  // The panorama was captured turned by 40 of its 512 columns (28.1 degrees); find the yaw
  // that undoes it the way holo::equirect applies a yaw, so the truth has the right sign.
  if (static_cast<int>(config_.placements.size()) != museum_.cameraCount())
    config_.placements = calib::defaultBoardPlacements(config_.placement_board, museum_.cameraCount());
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

const RgbdFrame& SimulatedRig::hallFrame(int camera) const {
  std::lock_guard lock(cache_mutex_);
  auto& frame = hall_frames_[camera];
  if (frame.empty()) frame = museum_.renderCamera(camera, 0, false).frame;
  return frame;
}

namespace {

// The 16 poses at which the technician holds the intrinsics board still, 0.3-0.45 m away,
// tilted, in every part of the wide picture (the corners constrain distortion, which otherwise
// trades off against the focal length): tilt x, tilt y, roll (degrees), centre x, y, z (metres).
constexpr int kHandHeldPoses = 16;
constexpr double kHandHeldPose[kHandHeldPoses][6] = {
    {0, 0, 0, 0.0, 0.0, 0.32},         {25, 0, 5, 0.25, 0.08, 0.35},      {-25, 0, -5, -0.25, -0.08, 0.35},
    {0, 30, 10, 0.3, -0.12, 0.38},     {0, -30, -10, -0.3, 0.12, 0.38},   {20, 20, 0, 0.0, 0.15, 0.32},
    {-20, 25, 15, 0.35, 0.0, 0.36},    {20, -25, -15, -0.35, 0.0, 0.36},  {-20, -20, 0, 0.0, -0.15, 0.32},
    {10, -30, 30, 0.3, 0.14, 0.36},    {-30, 10, -20, -0.3, -0.14, 0.36}, {15, 15, 45, 0.3, -0.15, 0.38},
    {-15, -15, -30, -0.3, 0.15, 0.38}, {30, 0, 90, 0.0, 0.0, 0.45},       {0, 35, 0, 0.15, 0.0, 0.3},
    {0, -35, 0, -0.15, 0.0, 0.3}};
// Per pose: one frame on the way there (moving) and two held still; then the board is taken away.
constexpr int kFramesPerHandHeldPose = 3;
constexpr int kFramesAway = 3;
// Per marked spot: the board stands three frames, then two frames without it while it is carried.
constexpr int kFramesAtSpot = 3;
constexpr int kFramesBetweenSpots = 2;
// The verification jig stands still: a few frames are enough.
constexpr int kFramesOfJig = 3;

cv::Matx44d handHeldPose(const BoardSpec& board, const double* p) {
  const double d = CV_PI / 180.0;
  cv::Matx33d Rx, Ry, Rz;
  cv::Rodrigues(cv::Vec3d(p[0] * d, 0, 0), Rx);
  cv::Rodrigues(cv::Vec3d(0, p[1] * d, 0), Ry);
  cv::Rodrigues(cv::Vec3d(0, 0, p[2] * d), Rz);
  const cv::Matx33d R = Rx * Ry * Rz;
  const cv::Rect2d e = board.extent();
  const cv::Vec3d t = cv::Vec3d(p[3], p[4], p[5]) - R * cv::Vec3d(e.x + e.width / 2, e.y + e.height / 2, 0);
  return {R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1],
          R(2, 0), R(2, 1), R(2, 2), t[2], 0,       0,       0,       1};
}

// True when every corner of the board's extent lies well in front of the camera (a board behind
// or beside the camera is not drawn: the homography would fold it into the picture).
bool inFrontOfCamera(const BoardSpec& board, const cv::Matx44d& T_camera_board) {
  const cv::Rect2d e = board.extent();
  for (const cv::Point3d corner :
       {cv::Point3d(e.x, e.y, 0), cv::Point3d(e.x + e.width, e.y, 0), cv::Point3d(e.x, e.y + e.height, 0),
        cv::Point3d(e.x + e.width, e.y + e.height, 0)})
    if (calib::transform(T_camera_board, corner).z < 0.1) return false;
  return true;
}

}  // namespace

std::string SimulatedRig::describe() const {
  return "simulated museum (scene " + scene_ + ")";
}

void SimulatedRig::begin(RigActivity activity) {
  activity_ = activity;
  next_.assign(static_cast<std::size_t>(cameraCount()), 0);
}

std::optional<RgbdFrame> SimulatedRig::nextFrame(int camera) {
  if (next_.empty()) next_.assign(static_cast<std::size_t>(cameraCount()), 0);
  int& index = next_.at(static_cast<std::size_t>(camera));
  if (index >= frameCount(activity_)) return std::nullopt;
  return frame(activity_, camera, index++);
}

int SimulatedRig::frameCount(RigActivity activity) const {
  switch (activity) {
    case RigActivity::HandHeldBoard:
      return kHandHeldPoses * kFramesPerHandHeldPose + kFramesAway;
    case RigActivity::PlacementBoard:
      return cameraCount() * (kFramesAtSpot + kFramesBetweenSpots);
    case RigActivity::EmptyHall:
      return config_.background_frames;
    case RigActivity::VerificationJig:
      return kFramesOfJig;
  }
  return 0;
}

RgbdFrame SimulatedRig::boardFrame(const BoardTexture& texture, const Intrinsics& K,
                                   const cv::Matx44d& T_camera_board, const cv::Matx44d& T_depth_board,
                                   int camera, std::uint64_t seed, float blur) const {
  const RgbdFrame& hall = hallFrame(camera);
  SyntheticViewOptions options;
  options.seed = seed;
  options.blur_sigma = blur;
  // The printed white reflects 85% of the hall's light: the camera does not saturate on it (the
  // colour matching refuses clipped white).
  static const cv::Mat paper = [] {
    cv::Mat table(1, 256, CV_8UC1);
    for (int v = 0; v < 256; ++v)
      table.at<std::uint8_t>(v) = cv::saturate_cast<std::uint8_t>(
          std::lround(255.0f * linearToSrgb(0.85f * srgbToLinear(static_cast<float>(v) / 255.0f))));
    return table;
  }();
  cv::Mat grey;
  cv::LUT(calib::renderBoardView(texture, K, T_camera_board, options, hall.colour), paper, grey);
  RgbdFrame out;
  cv::cvtColor(grey, out.colour, cv::COLOR_GRAY2BGR);
  // The depth device sees the board where it stood depth_delay_s_ later (the same pose while it
  // is held still), with a structured-light camera's noise at that distance.
  const double z = T_depth_board(2, 3);
  const cv::Mat board =
      calib::renderBoardDepth(texture, K, T_depth_board, 0.001 + 0.0025 * z * z, seed ^ 0xde97full);
  out.depth = hall.depth.clone();
  board.copyTo(out.depth, board > 0);
  return out;
}

RgbdFrame SimulatedRig::frame(RigActivity activity, int camera, int index) const {
  const Intrinsics& K = trueCamera(camera).intrinsics();
  RgbdFrame out;
  switch (activity) {
    case RigActivity::HandHeldBoard: {
      const int pose = index / kFramesPerHandHeldPose, step = index % kFramesPerHandHeldPose;
      if (pose >= kHandHeldPoses) {
        out = hallFrame(camera);
        out.colour = out.colour.clone();
        break;
      }
      cv::Matx44d T = handHeldPose(config_.intrinsics_board, kHandHeldPose[pose]), T_depth = T;
      if (step == 0) {
        // On the way from the previous pose: half-way there (the frame before arrives a frame
        // period earlier), and blurred by the motion; the depth device sees it further along.
        const double* from = kHandHeldPose[pose == 0 ? kHandHeldPoses - 1 : pose - 1];
        const double fps = museum_.description().camera.fps;
        const auto between = [&](double share) {
          double p[6];
          for (int i = 0; i < 6; ++i) p[i] = from[i] + share * (kHandHeldPose[pose][i] - from[i]);
          return handHeldPose(config_.intrinsics_board, p);
        };
        T = between(0.5);
        T_depth = between(std::min(1.0, 0.5 + 0.5 * depth_delay_s_ * fps));
      }
      out = boardFrame(intrinsics_texture_, K, T, T_depth, camera,
                       static_cast<std::uint64_t>(1000 + 100 * camera + index), step == 0 ? 1.5f : 0.0f);
      break;
    }
    case RigActivity::PlacementBoard: {
      const int spot = index / (kFramesAtSpot + kFramesBetweenSpots);
      const cv::Matx44d T = calib::rigidInverse(calib::toMatx(trueCamera(camera).T_world_camera())) *
                            config_.placements[static_cast<std::size_t>(spot)];
      if (index % (kFramesAtSpot + kFramesBetweenSpots) >= kFramesAtSpot ||
          !inFrontOfCamera(config_.placement_board, T)) {
        out = hallFrame(camera);
        out.colour = out.colour.clone();
        break;
      }
      out = boardFrame(placement_texture_, K, T, T, camera,
                       static_cast<std::uint64_t>(2000 + 100 * camera + index), 0.5f);
      break;
    }
    case RigActivity::EmptyHall:
      out = museum_.renderCamera(camera, index, false).frame;
      break;
    case RigActivity::VerificationJig: {
      cv::Matx44d T_world_camera = calib::toMatx(trueCamera(camera).T_world_camera());
      if (const auto knock = knocked_.find(camera); knock != knocked_.end())
        T_world_camera = T_world_camera * knock->second;
      const cv::Matx44d T = calib::rigidInverse(T_world_camera) * calib::verificationTargetPose(camera);
      out = boardFrame(verification_texture_, K, T, T, camera,
                       static_cast<std::uint64_t>(4000 + 100 * camera + index), 0.5f);
      break;
    }
  }
  out.camera_id = camera;
  out.sequence = static_cast<std::uint64_t>(index);
  out.device_time =
      Nanoseconds(std::llround(index * 1e9 / static_cast<double>(museum_.description().camera.fps)));
  return out;
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
  const cv::Matx23d A = calib::faceTransform(trueFaceAlignment(face), view);
  cv::RNG rng(static_cast<std::uint64_t>(3000 + face));
  std::vector<cv::Point2f> observed;
  for (const auto& p : calib::testPatternDots(view)) {
    const cv::Vec2d q = A * cv::Vec3d(p.x, p.y, 1.0);
    observed.emplace_back(static_cast<float>(q[0] + rng.gaussian(0.3)),
                          static_cast<float>(q[1] + rng.gaussian(0.3)));
  }
  return observed;
}

}  // namespace holo::simulated
