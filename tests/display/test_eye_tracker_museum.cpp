// The eye of the face a visitor stands at follows him as he walks around the pyramid, in the
// simulated museum: four noisy depth cameras render the visitor, his foreground pixels are
// back-projected into a world cloud (what the depth filter hands over, without its filtering)
// and the tracker is compared with the simulation's own head positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "holo/display/eye_tracker.hpp"
#include "holo/sim/museum.hpp"

namespace holo::display {
namespace {

// The foreground cloud of one frame: every foreground pixel with a depth, in the world frame.
depthfilter::ForegroundCloud foregroundCloud(const sim::Museum& museum, int frame,
                                             const std::vector<std::vector<vec3>>& directions) {
  depthfilter::ForegroundCloud cloud;
  cloud.sequence = frame;
  cloud.time_s = museum.frameTime(frame);
  for (int c = 0; c < museum.cameraCount(); ++c) {
    const sim::SimulatedFrame shot = museum.renderCamera(c, frame);
    const mat4& T = museum.camera(c).T_world_camera();
    const std::vector<vec3>& table = directions[static_cast<std::size_t>(c)];
    for (int y = 0; y < shot.frame.depth.rows; ++y)
      for (int x = 0; x < shot.frame.depth.cols; ++x) {
        const float depth = shot.frame.depth.at<float>(y, x);
        if (shot.foreground.at<uchar>(y, x) == 0 || !(depth > 0.0f)) continue;
        depthfilter::ForegroundPoint point;
        point.position =
            transformPoint(T, table[static_cast<std::size_t>(y * shot.frame.depth.cols + x)] * depth);
        point.camera = static_cast<std::uint16_t>(c);
        point.x = static_cast<std::uint16_t>(x);
        point.y = static_cast<std::uint16_t>(y);
        cloud.points.push_back(point);
      }
  }
  return cloud;
}

// The face whose sector holds `p`, and how far (degrees) `p` is from the sector's border.
int sectorOf(const vec3& p, float& margin_deg) {
  const float azimuth = std::atan2(p.x, p.z) * 180.0f / kPi;  // 0 = +Z, 90 = +X
  const int face = static_cast<int>(std::lround(azimuth / 90.0f) + 4) % kFaceCount;
  const float from_centre = std::abs(std::remainder(azimuth - static_cast<float>(face) * 90.0f, 360.0f));
  margin_deg = 45.0f - from_centre;
  return face;
}

TEST(EyeTrackerMuseum, EyeOfTheFaceHeStandsAtMovesWithHim) {
  sim::SceneDescription scene = sim::loadScene("museum");
  scene.visitors = 1;
  scene.camera.width = 320;  // a quarter of the pixels keeps the test quick; same field of view
  scene.camera.height = 180;
  const sim::Museum museum(scene);
  std::vector<std::vector<vec3>> directions;
  for (int c = 0; c < museum.cameraCount(); ++c) directions.push_back(museum.camera(c).planeDirectionTable());

  EyeTracker tracker;  // defaults match the museum: floor at y = -1
  std::vector<float> errors;
  float vertical_sum = 0.0f;
  int checked = 0, moved_with_him = 0, steps = 0;
  vec3 previous_eye(0.0f), previous_head(0.0f);
  int previous_face = -1;
  constexpr int kStride = 3;  // 10 updates per second of a 30 fps museum
  for (int frame = 0; frame < 240; frame += kStride) {
    const auto& eyes = tracker.update(foregroundCloud(museum, frame, directions));
    const vec3 head = museum.visitorHeads(frame).at(0);
    float margin = 0.0f;
    const int face = sectorOf(head, margin);
    if (margin < 8.0f || frame < 2 * kStride) {
      previous_face = -1;  // near a sector border the neighbouring face may take him: skip
      continue;
    }
    const FaceEye& eye = eyes[static_cast<std::size_t>(face)];
    EXPECT_TRUE(eye.tracked) << "frame " << frame << " face " << face;
    ++checked;
    // Where he looks from: 8 cm in front of his head's centre, towards the pyramid.
    const vec3 anatomical_eye = head + 0.08f * glm::normalize(vec3(-head.x, 0.0f, -head.z));
    const vec3 error = eye.position - anatomical_eye;
    errors.push_back(glm::length(error));
    vertical_sum += error.y;
    // "With him" needs him to move: the articulated visitor stands still for seconds (his head
    // moves 0 mm between those updates), where any eye jitter would count against the tracker.
    if (previous_face == face && glm::length(head - previous_head) > 0.001f) {
      ++steps;
      if (glm::dot(eye.position - previous_eye, head - previous_head) > 0.0f) ++moved_with_him;
    }
    previous_face = face;
    previous_eye = eye.position;
    previous_head = head;
  }
  ASSERT_GT(checked, 30);
  std::sort(errors.begin(), errors.end());
  const float median = errors[errors.size() / 2];
  const float p90 = errors[errors.size() * 9 / 10];
  RecordProperty("median_error_mm", static_cast<int>(median * 1000));
  RecordProperty("p90_error_mm", static_cast<int>(p90 * 1000));
  const float vertical_bias = vertical_sum / static_cast<float>(errors.size());
  RecordProperty("vertical_bias_mm", static_cast<int>(vertical_bias * 1000));
  // The base's cameras look up at the head and barely see its top, so the eye comes out about
  // 3 cm low; walking adds the filter's lag along his path. Measured (articulated visitor who
  // stops and raises an arm): median 33 mm, p90 46 mm, vertical bias -32 mm.
  EXPECT_LT(median, 0.10f) << "p90 " << p90 << ", vertical bias " << vertical_bias;
  EXPECT_LT(p90, 0.15f) << "median " << median << ", vertical bias " << vertical_bias;
  EXPECT_GE(moved_with_him, steps * 9 / 10) << "of " << steps << " steps";
}

}  // namespace
}  // namespace holo::display
