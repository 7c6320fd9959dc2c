// segmentPeople: people separated from the room in a single depth frame by depth continuity from
// seeds, with the floor cut off. Checked where the truth is known (simulated frames, whose true
// foreground gives the seeds and the answer) and on the real Kinect frame with two people.
#include <gtest/gtest.h>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/sim/depth_statistics.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/person_segmentation.hpp"
#include "shared_data.hpp"
#include "tum_walking.hpp"

namespace holo::sim {
namespace {

// On the default museum's cameras (structured-light holes and noise), the grown people cover the
// visitors' measured pixels and little else: intersection over union with the true foreground's
// measured pixels above 0.9 (measured 0.983), pooled over frames 5 and 20 of the four cameras.
TEST(PersonSegmentation, FindsTheSimulatedVisitorsFromOneSeedEach) {
  const Museum museum(loadScene("museum"));
  long long both = 0, either = 0;
  for (int frame : {5, 20})
    for (int camera = 0; camera < museum.cameraCount(); ++camera) {
      const SimulatedFrame f = museum.renderCamera(camera, frame);
      const auto seeds = seedsFromMask(f.foreground, f.frame.depth, museum.camera(camera).intrinsics());
      const cv::Mat truth = (f.foreground != 0) & (f.frame.depth > 0.0f);
      if (seeds.empty()) {
        EXPECT_LT(cv::countNonZero(truth), 200);
        continue;
      }
      const cv::Mat grown = segmentPeople(f.frame.depth, museum.camera(camera).intrinsics(), seeds);
      const cv::Mat measured = grown & (f.frame.depth > 0.0f);
      both += cv::countNonZero(measured & truth);
      either += cv::countNonZero(measured | truth);
    }
  ASSERT_GT(either, 5000);
  const double iou = double(both) / double(either);
  std::printf("intersection over union with the true visitors: %.3f (%lld px)\n", iou, either);
  EXPECT_GT(iou, 0.9);
}

TEST(PersonSegmentation, ASeedWithoutDepthIsAnError) {
  cv::Mat depth(40, 40, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(10, 10) = 0.0f;
  Intrinsics K;
  K.width = K.height = 40;
  K.fx = K.fy = 40.0f;
  K.cx = K.cy = 20.0f;
  EXPECT_THROW(segmentPeople(depth, K, {{10, 10}}), Error);
  EXPECT_THROW(segmentPeople(depth, K, {{40, 3}}), Error);
  EXPECT_EQ(cv::countNonZero(segmentPeople(depth, K, {{3, 3}})), 40 * 40);  // its enclosed hole joins it
}

// The real frame: each person is one region of plausible size, the two stay apart, and the
// room (the partition between them, a monitor, the floor in front) stays out.
TEST(PersonSegmentation, SeparatesTheTwoPeopleOfTheRealKinectFrame) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum_walking/depth.png");
  const cv::Mat depth =
      loadDepthPng(test::sharedData("rgbd/tum_walking/depth.png").string(), test::kTumDepthUnitsPerMetre);
  const auto seeds = test::tumWalkingPersonSeeds();
  const cv::Mat people = segmentPeople(depth, test::tumFr3Intrinsics(), seeds);
  cv::Mat labels;
  const int regions = cv::connectedComponents(people, labels, 8, CV_32S) - 1;
  const int sitting = labels.at<int>(seeds[0]), standing = labels.at<int>(seeds[1]);
  const int sitting_px = cv::countNonZero(labels == sitting),
            standing_px = cv::countNonZero(labels == standing);
  std::printf("people: %d regions, sitting %d px, standing %d px\n", regions, sitting_px, standing_px);
  EXPECT_EQ(regions, 2);
  EXPECT_NE(sitting, standing);
  EXPECT_GT(sitting_px, 20000);  // measured 36k of 307k pixels
  EXPECT_LT(sitting_px, 60000);
  EXPECT_GT(standing_px, 30000);  // measured 52k
  EXPECT_LT(standing_px, 80000);
  for (const cv::Point room :
       {cv::Point(320, 150), cv::Point(420, 230), cv::Point(320, 460), cv::Point(250, 150)})
    EXPECT_EQ(people.at<std::uint8_t>(room), 0) << room;
}

}  // namespace
}  // namespace holo::sim
