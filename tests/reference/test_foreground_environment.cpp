// The paper's IBL baseline environment (foreground_environment.hpp): the foreground cloud drawn
// over the static panorama, nearer points winning, half-weight points blended, bad points rejected.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reference/foreground_environment.hpp"

namespace holo::reference {
namespace {

vec3 nearestPixel(const cv::Mat& pano, const vec3& d) {
  const vec2 uv = equirect::directionToUv(d);
  return rgbAt(pano, std::min(int(uv.x * pano.cols), pano.cols - 1),
               std::min(int(uv.y * pano.rows), pano.rows - 1));
}

TEST(ForegroundEnvironment, NearerPointsWinAndBadPointsAreRejected) {
  const cv::Mat pano(64, 128, CV_32FC3, cv::Scalar::all(0.25));
  depthfilter::ForegroundCloud cloud;
  const auto add = [&](vec3 p, vec3 c, float weight = 1.0f) {
    depthfilter::ForegroundPoint point;
    point.position = p;
    point.radiance = c;
    point.weight = weight;
    cloud.points.push_back(point);
  };
  const vec3 centre(0, 1, 0);
  add(centre + vec3(2, 0, 0), vec3(1, 0, 0));         // far red, towards +X
  add(centre + vec3(1, 0, 0), vec3(0, 1, 0));         // near green, same direction: wins
  add(centre + vec3(0, 0, -1), vec3(0, 0, 1), 0.5f);  // half-weight blue towards -Z
  add(vec3(NAN, 0, 0), vec3(1));
  add(centre, vec3(1));                        // at the centre: no direction
  add(centre + vec3(0, 1, 0), vec3(1), 0.0f);  // weight 0
  ReprojectionStats stats;
  const cv::Mat merged = mergeForeground(pano, cloud, centre, 0.05f, 0.0f, &stats);
  EXPECT_EQ(stats.points_used, 3);
  EXPECT_EQ(stats.points_rejected, 3);
  EXPECT_GT(stats.pixels_covered, 3);
  EXPECT_NEAR(nearestPixel(merged, vec3(1, 0, 0)).g, 1.0f, 1e-4f);
  EXPECT_NEAR(nearestPixel(merged, vec3(1, 0, 0)).r, 0.0f, 1e-4f);
  const vec3 blue = nearestPixel(merged, vec3(0, 0, -1));
  EXPECT_NEAR(blue.b, 0.5f * 1.0f + 0.5f * 0.25f, 1e-4f);
  EXPECT_NEAR(blue.r, 0.5f * 0.25f, 1e-4f);
  EXPECT_NEAR(nearestPixel(merged, vec3(-1, 0, 0)).r, 0.25f, 1e-6f);  // untouched
  EXPECT_THROW(mergeForeground(cv::Mat(), cloud, centre), InputError);
}

}  // namespace
}  // namespace holo::reference
