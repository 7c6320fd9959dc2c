// A camera rig like the simulated museum's: four 640x360 cameras (110 x 70 degree field of view)
// on the four sides of a 0.6 m base, 0.12 m below its top, looking outward and tilted up 8
// degrees; and, for each, a ChArUco board standing on an easel at a marked spot in front of it.
#pragma once

#include <vector>

#include "board_poses.hpp"
#include "holo/calib/pose.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::calib::test {

inline Intrinsics rigIntrinsics() {
  Intrinsics K = Intrinsics::fromFov(640, 360, 110.0f * kPi / 180.0f, 70.0f * kPi / 180.0f);
  K.distortion = {-0.05f, 0.01f, 0.0f, 0.0f, 0.0f};
  return K;
}

inline cv::Matx44d rigCamera(int face) {
  const float azimuth = static_cast<float>(face) * 0.5f * kPi;
  const vec3 out{std::sin(azimuth), 0.0f, std::cos(azimuth)};
  const vec3 eye = 0.305f * out - vec3(0.0f, 0.12f, 0.0f);
  const float tilt = 8.0f * kPi / 180.0f;
  return toMatx(lookAtCameraToWorld(eye, eye + std::cos(tilt) * out + vec3(0.0f, std::sin(tilt), 0.0f)));
}

// The easel spot in front of camera `face`: 0.75 m out, turned and leaned a little so the
// pose is well conditioned, as the technician's floor markings would place it.
inline cv::Matx44d rigBoardPlacement(const BoardSpec& board, int face) {
  const double turn = face % 2 == 0 ? 20.0 : -20.0;
  return rigCamera(face) * boardPose(board, 12.0, turn, 3.0 * face, {0.03, 0.02, 0.75});
}

}  // namespace holo::calib::test
