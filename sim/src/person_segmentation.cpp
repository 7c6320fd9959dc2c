#include "holo/sim/person_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::sim {

namespace {

constexpr int kSampleStride = 4;
constexpr std::uint64_t kRansacSeed = 0x5e65ull;
constexpr float kMinCameraHeight = 0.3f;  // metres above the floor

struct Plane {
  cv::Vec3f normal;  // unit
  float offset = 0;  // normal . p + offset = 0
  bool valid = false;
};

cv::Vec3f backProject(const Intrinsics& K, int x, int y, float z) {
  return {(static_cast<float>(x) - K.cx) * z / K.fx, (static_cast<float>(y) - K.cy) * z / K.fy, z};
}

// The floor: among planes at least kMinCameraHeight below the camera, with at most 2% of the
// points below them, through three sampled points whose
// normal is within kFloorTiltDeg of the image's up axis (-y), the one with the most inliers. No floor in view
// gives !valid.
Plane fitFloor(const cv::Mat& depth, const Intrinsics& K, const PersonSegmentationConfig& config) {
  std::vector<cv::Vec3f> points;
  for (int y = 0; y < depth.rows; y += kSampleStride)
    for (int x = 0; x < depth.cols; x += kSampleStride)
      if (const float z = depth.at<float>(y, x); z > 0.0f) points.push_back(backProject(K, x, y, z));
  Plane best;
  if (points.size() < 3) return best;
  const float min_up = std::cos(kFloorTiltDeg * static_cast<float>(CV_PI) / 180.0f);
  cv::RNG rng(kRansacSeed);
  int best_inliers = 0;
  const int n = static_cast<int>(points.size());
  for (int i = 0; i < config.ransac_iterations; ++i) {
    const cv::Vec3f& a = points[static_cast<std::size_t>(rng.uniform(0, n))];
    const cv::Vec3f& b = points[static_cast<std::size_t>(rng.uniform(0, n))];
    const cv::Vec3f& c = points[static_cast<std::size_t>(rng.uniform(0, n))];
    cv::Vec3f normal = (b - a).cross(c - a);
    const float length = static_cast<float>(cv::norm(normal));
    if (length < 1e-6f) continue;
    normal /= length;
    if (normal[1] > 0.0f) normal = -normal;  // point it up (image -y)
    if (-normal[1] < min_up) continue;
    const float offset = -normal.dot(a);
    // The floor is well below the camera: not a ceiling, not a plane grazing a nearby body.
    if (offset < kMinCameraHeight) continue;
    int inliers = 0, below = 0;
    for (const cv::Vec3f& p : points) {
      const float distance = normal.dot(p) + offset;
      inliers += std::abs(distance) < config.floor_tolerance;
      below += distance < -2.0f * config.floor_tolerance;
    }
    // Nothing stands below the floor: a plane with points beneath it cuts through the room.
    if (below > n / 50) continue;
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = {normal, offset, true};
    }
  }
  return best;
}

}  // namespace

float maxStep(const PersonSegmentationConfig& config, const Intrinsics& K, float z) {
  return config.step_m + config.step_rel * z + config.max_slope * z / K.fx;
}

cv::Mat segmentPeople(const cv::Mat& depth, const Intrinsics& K, const std::vector<cv::Point>& seeds,
                      const PersonSegmentationConfig& config) {
  CV_Assert(depth.type() == CV_32FC1);
  const cv::Rect image(0, 0, depth.cols, depth.rows);
  for (const cv::Point& s : seeds)
    if (!image.contains(s) || !(depth.at<float>(s) > 0.0f))
      throw Error("segmentPeople: seed (" + std::to_string(s.x) + ", " + std::to_string(s.y) +
                  ") is outside the image or has no depth");
  const Plane floor = fitFloor(depth, K, config);
  const auto isFloor = [&](int x, int y, float z) {
    return floor.valid &&
           std::abs(floor.normal.dot(backProject(K, x, y, z)) + floor.offset) < config.floor_margin;
  };
  cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8UC1);
  std::deque<cv::Point> queue;
  for (const cv::Point& s : seeds) {
    mask.at<std::uint8_t>(s) = 255;
    queue.push_back(s);
  }
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  while (!queue.empty()) {
    const cv::Point p = queue.front();
    queue.pop_front();
    const float z = depth.at<float>(p);
    for (int k = 0; k < 4; ++k) {
      const cv::Point q(p.x + dx[k], p.y + dy[k]);
      if (!image.contains(q) || mask.at<std::uint8_t>(q)) continue;
      const float zq = depth.at<float>(q);
      if (!(zq > 0.0f) || std::abs(zq - z) > maxStep(config, K, std::min(z, zq))) continue;
      if (isFloor(q.x, q.y, zq)) continue;
      mask.at<std::uint8_t>(q) = 255;
      queue.push_back(q);
    }
  }
  // Holes enclosed by the people: every hole component that does not reach the image border or
  // a valid pixel outside the mask.
  cv::Mat holes = (depth <= 0.0f) & ~mask;
  cv::Mat labels;
  const int count = cv::connectedComponents(holes, labels, 4, CV_32S);
  std::vector<char> open(static_cast<std::size_t>(count), 0);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const int label = labels.at<int>(y, x);
      if (label == 0) continue;
      if (x == 0 || y == 0 || x == depth.cols - 1 || y == depth.rows - 1) open[std::size_t(label)] = 1;
      for (int k = 0; k < 4; ++k) {
        const cv::Point q(x + dx[k], y + dy[k]);
        if (image.contains(q) && depth.at<float>(q) > 0.0f && !mask.at<std::uint8_t>(q))
          open[std::size_t(label)] = 1;
      }
    }
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x)
      if (const int label = labels.at<int>(y, x); label > 0 && !open[std::size_t(label)])
        mask.at<std::uint8_t>(y, x) = 255;
  return mask;
}

std::vector<cv::Point> seedsFromMask(const cv::Mat& mask, const cv::Mat& depth, const Intrinsics& K,
                                     int min_pixels, const PersonSegmentationConfig& config) {
  CV_Assert(mask.type() == CV_8UC1 && depth.type() == CV_32FC1 && mask.size() == depth.size());
  const cv::Rect image(0, 0, depth.cols, depth.rows);
  cv::Mat visited = cv::Mat::zeros(depth.size(), CV_8UC1);
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  std::vector<cv::Point> seeds;
  for (int y0 = 0; y0 < depth.rows; ++y0)
    for (int x0 = 0; x0 < depth.cols; ++x0) {
      if (visited.at<std::uint8_t>(y0, x0) || !mask.at<std::uint8_t>(y0, x0) ||
          !(depth.at<float>(y0, x0) > 0.0f))
        continue;
      // One depth-continuous part of the mask, grown with segmentPeople's step.
      std::vector<cv::Point> part{{x0, y0}};
      visited.at<std::uint8_t>(y0, x0) = 255;
      cv::Point2d sum(0, 0);
      for (std::size_t i = 0; i < part.size(); ++i) {
        const cv::Point p = part[i];
        sum += cv::Point2d(p.x, p.y);
        const float z = depth.at<float>(p);
        for (int k = 0; k < 4; ++k) {
          const cv::Point q(p.x + dx[k], p.y + dy[k]);
          if (!image.contains(q) || visited.at<std::uint8_t>(q) || !mask.at<std::uint8_t>(q)) continue;
          const float zq = depth.at<float>(q);
          if (!(zq > 0.0f) || std::abs(zq - z) > maxStep(config, K, std::min(z, zq))) continue;
          visited.at<std::uint8_t>(q) = 255;
          part.push_back(q);
        }
      }
      if (static_cast<int>(part.size()) < min_pixels) continue;
      const cv::Point2d centroid = sum / static_cast<double>(part.size());
      const auto distance = [&](const cv::Point& p) {
        return (p.x - centroid.x) * (p.x - centroid.x) + (p.y - centroid.y) * (p.y - centroid.y);
      };
      seeds.push_back(*std::min_element(
          part.begin(), part.end(),
          [&](const cv::Point& a, const cv::Point& b) { return distance(a) < distance(b); }));
    }
  return seeds;
}

}  // namespace holo::sim
