// The real Kinect frame with two people (TUM RGB-D fr3/walking_xyz, ../shared/data/rgbd/
// tum_walking: colour and depth registered, 640x480, depth 5000 units per metre) and where its
// people are, for holo::sim::segmentPeople: one seed pixel on each person's shirt, picked by eye
// on color.png (the man sitting at the desk on the left, the man standing on the right).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/core/camera_model.hpp"

namespace holo::test {

inline constexpr double kTumDepthUnitsPerMetre = 5000.0;

// TUM's published intrinsics of the fr3 Kinect's colour camera (the depth is registered to it).
inline Intrinsics tumFr3Intrinsics() {
  Intrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = 535.4f;
  K.fy = 539.2f;
  K.cx = 320.1f;
  K.cy = 247.6f;
  return K;
}

inline std::vector<cv::Point> tumWalkingPersonSeeds() {
  return {{95, 250}, {560, 250}};
}

}  // namespace holo::test
