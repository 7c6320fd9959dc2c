// People in a single real depth frame, separated from the room without a background model (a
// real test frame such as TUM's walking_xyz is one frame: there is no empty room to subtract).
// Used to measure holes on people against holes elsewhere (depth_statistics.hpp) and to give the
// depth filter's tests a person mask on real frames (docs/sim.md, "People in a real frame").
//
// Method (pixels; depth CV_32FC1 metres, 0 = hole):
//   1. the floor: the plane through the most valid points (RANSAC over every 4th pixel, fixed
//      seed) among planes 0.3 m or more below the camera with at most 2% of the points below them whose
//      normal is within kFloorTiltDeg of the image's up axis; points within floor_margin of it are never a
//      person (feet stand on it, so growth would leak);
//   2. region growing from the given seed pixels over 4-neighbours whose depths differ by at
//      most step_m + step_rel * z + max_slope * z / fx: a body is depth-continuous, the room
//      behind it is not;
//   3. holes enclosed by the grown region (hair, dark clothes, the shadow strip inside an arm)
//      join it: a person's hole is a hole on the person.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/core/camera_model.hpp"

namespace holo::sim {

inline constexpr float kFloorTiltDeg = 40.0f;

struct PersonSegmentationConfig {
  float step_m = 0.012f;    // largest depth step between neighbouring pixels of one body ...
  float step_rel = 0.006f;  // ... plus this share of the depth
  // ... plus this slope times the pixel footprint z / fx: a slanted surface steps further per
  // pixel in a wide-angle camera (3: up to 72 degrees from facing the camera).
  float max_slope = 3.0f;
  float floor_margin = 0.05f;     // points this close to the floor plane are floor, metres
  float floor_tolerance = 0.03f;  // RANSAC inlier distance, metres
  int ransac_iterations = 400;
};

// CV_8UC1, 255 on the people grown from `seeds` (pixel coordinates on a valid depth of each
// person). Throws holo::Error when a seed is outside the image or has no depth.
cv::Mat segmentPeople(const cv::Mat& depth, const Intrinsics& K, const std::vector<cv::Point>& seeds,
                      const PersonSegmentationConfig& config = {});

// Seeds from a known mask (a simulated frame's true foreground), so that a simulated frame is
// segmented exactly as a real one and holes on people are counted alike: one seed for every
// depth-continuous part of the mask's measured pixels (grown with config's step, inside the mask)
// of at least min_pixels, its pixel nearest the part's centroid. A simulated visitor's limbs are
// separate solids, so each gets its own seed, as a real body's continuous surface would not need.
std::vector<cv::Point> seedsFromMask(const cv::Mat& mask, const cv::Mat& depth, const Intrinsics& K,
                                     int min_pixels = 200, const PersonSegmentationConfig& config = {});
// The largest depth step between neighbouring pixels of one body at depth z (metres).
float maxStep(const PersonSegmentationConfig& config, const Intrinsics& K, float z);

}  // namespace holo::sim
