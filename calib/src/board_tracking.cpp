#include "holo/calib/board_tracking.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/calib/pose.hpp"

namespace holo::calib {

namespace {

// Two views closer than all of these are the same view for intrinsics.
constexpr double kSameCentre = 0.08;  // fraction of the image (Euclidean over width, height)
constexpr double kSameSize = 0.15;    // relative difference of the width fraction
constexpr double kSameTiltDeg = 8.0;

}  // namespace

const char* toString(ViewPose::Direction direction) {
  switch (direction) {
    case ViewPose::Frontal:
      return "frontal";
    case ViewPose::Right:
      return "right";
    case ViewPose::Down:
      return "bottom";
    case ViewPose::Left:
      return "left";
    case ViewPose::Up:
      return "top";
  }
  return "?";
}

ViewPose describeView(const BoardDetection& detection, cv::Size image) {
  ViewPose view;
  cv::Point2d centre(0, 0), board_centre(0, 0);
  for (std::size_t i = 0; i < detection.image_points.size(); ++i) {
    centre += cv::Point2d(detection.image_points[i]);
    board_centre += cv::Point2d(detection.object_points[i].x, detection.object_points[i].y);
  }
  const double n = static_cast<double>(detection.image_points.size());
  centre *= 1.0 / n;
  board_centre *= 1.0 / n;
  view.centre = {centre.x / image.width, centre.y / image.height};
  view.width_fraction = detection.widthFraction(image.width);

  std::vector<cv::Point2f> board_xy;
  for (const auto& p : detection.object_points) board_xy.emplace_back(p.x, p.y);
  cv::Mat H = cv::findHomography(board_xy, detection.image_points);
  if (H.empty()) return view;
  cv::Matx33d h(H);
  const double x = board_centre.x, y = board_centre.y;
  double w = h(2, 0) * x + h(2, 1) * y + h(2, 2);
  if (w < 0) {  // scale the homography so that w is the (positive) depth up to a factor
    h = -h;
    w = -w;
  }
  const double u = (h(0, 0) * x + h(0, 1) * y + h(0, 2)) / w;
  const double v = (h(1, 0) * x + h(1, 1) * y + h(1, 2)) / w;
  const cv::Matx22d J((h(0, 0) - u * h(2, 0)) / w, (h(0, 1) - u * h(2, 1)) / w, (h(1, 0) - v * h(2, 0)) / w,
                      (h(1, 1) - v * h(2, 1)) / w);
  cv::Mat s;
  cv::SVD::compute(cv::Mat(J), s, cv::SVD::NO_UV);
  const double s1 = s.at<double>(0), s2 = s.at<double>(1);
  view.tilt_deg = s1 > 0 ? std::acos(std::clamp(s2 / s1, 0.0, 1.0)) * 180.0 / CV_PI : 0.0;
  if (view.tilt_deg < kFrontalTiltDeg) return view;
  // w grows (the board is further away) along the board direction (h31, h32); in the image that
  // is J times it.
  const cv::Vec2d further = J * cv::Vec2d(h(2, 0), h(2, 1));
  const double angle = std::atan2(further[1], further[0]) * 180.0 / CV_PI;  // image y points down
  view.direction = std::abs(angle) <= 45.0        ? ViewPose::Right
                   : angle > 45 && angle <= 135   ? ViewPose::Down
                   : angle < -45 && angle >= -135 ? ViewPose::Up
                                                  : ViewPose::Left;
  return view;
}

std::optional<cv::Matx44d> boardPose(const BoardDetection& detection, const Intrinsics& intrinsics) {
  if (!detection.usable()) return std::nullopt;
  const cv::Matx33d K(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
  std::vector<double> dist(intrinsics.distortion.begin(), intrinsics.distortion.end());
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(detection.object_points, detection.image_points, K, dist, rvec, tvec))
    return std::nullopt;
  return poseFromRt(rvec, tvec);
}

double cornerMotion(const BoardDetection& previous, const BoardDetection& current) {
  std::map<int, cv::Point2f> before;
  for (std::size_t i = 0; i < previous.ids.size(); ++i) before[previous.ids[i]] = previous.image_points[i];
  double sum = 0;
  int shared = 0;
  for (std::size_t i = 0; i < current.ids.size(); ++i) {
    const auto it = before.find(current.ids[i]);
    if (it == before.end()) continue;
    sum += cv::norm(current.image_points[i] - it->second);
    ++shared;
  }
  return shared >= 4 ? sum / shared : -1.0;
}

void CoverageGrid::add(const ViewPose& view) {
  const auto cell = [](double f) { return std::clamp(static_cast<int>(f * kCells), 0, kCells - 1); };
  ++image[static_cast<std::size_t>(cell(view.centre.y) * kCells + cell(view.centre.x))];
  ++tilt[static_cast<std::size_t>(view.direction)];
}

int CoverageGrid::imageCellsFilled() const {
  return static_cast<int>(std::count_if(image.begin(), image.end(), [](int n) { return n > 0; }));
}

int CoverageGrid::tiltClassesFilled() const {
  return static_cast<int>(std::count_if(tilt.begin(), tilt.end(), [](int n) { return n > 0; }));
}

std::string CoverageGrid::describe() const {
  std::ostringstream out;
  out << "image " << imageCellsFilled() << "/" << image.size() << " cells, tilt " << tiltClassesFilled()
      << "/" << tilt.size() << " (";
  bool first = true;
  for (int d = 0; d < static_cast<int>(tilt.size()); ++d)
    if (tilt[static_cast<std::size_t>(d)] > 0) {
      out << (first ? "" : " ") << toString(static_cast<ViewPose::Direction>(d));
      first = false;
    }
  out << ")";
  return out.str();
}

void CoverageGrid::draw(cv::Mat& picture) const {
  const cv::Scalar filled(60, 200, 60), empty(80, 80, 230);
  cv::Mat overlay = picture.clone();
  for (int r = 0; r < kCells; ++r)
    for (int c = 0; c < kCells; ++c) {
      const cv::Rect cell(c * picture.cols / kCells, r * picture.rows / kCells, picture.cols / kCells,
                          picture.rows / kCells);
      if (image[static_cast<std::size_t>(r * kCells + c)] > 0)
        cv::rectangle(overlay, cell, filled, cv::FILLED);
      cv::rectangle(picture, cell, image[static_cast<std::size_t>(r * kCells + c)] > 0 ? filled : empty, 1);
    }
  cv::addWeighted(overlay, 0.25, picture, 0.75, 0.0, picture);
  const int box = std::max(12, picture.rows / 14);
  for (int d = 0; d < static_cast<int>(tilt.size()); ++d) {
    const cv::Rect r(4 + d * (box + 4), picture.rows - box - 4, box, box);
    const bool has = tilt[static_cast<std::size_t>(d)] > 0;
    cv::rectangle(picture, r, has ? filled : empty, has ? cv::FILLED : 2);
    // An arrow from the box's centre toward the side that is further away (none for frontal).
    const cv::Point mid(r.x + box / 2, r.y + box / 2);
    static const cv::Point kArrow[] = {{0, 0}, {1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    if (d > 0) cv::arrowedLine(picture, mid, mid + kArrow[d] * (box / 2 - 2), cv::Scalar(20, 20, 20), 1);
  }
}

IntrinsicsViewSelector::IntrinsicsViewSelector(BoardSpec board, int camera, cv::Size image_size, bool stills)
    : board_(std::move(board)), camera_(camera), image_size_(image_size), stills_(stills) {}

bool IntrinsicsViewSelector::nearCopy(const ViewPose& view) const {
  return std::any_of(kept_poses_.begin(), kept_poses_.end(), [&](const ViewPose& kept) {
    const bool same_direction = kept.direction == view.direction;
    return cv::norm(kept.centre - view.centre) < kSameCentre &&
           std::abs(kept.width_fraction - view.width_fraction) < kSameSize * kept.width_fraction &&
           std::abs(kept.tilt_deg - view.tilt_deg) < kSameTiltDeg && same_direction;
  });
}

const BoardFrameObservation& IntrinsicsViewSelector::add(const RgbdFrame& frame, const std::string& name) {
  BoardFrameObservation obs;
  obs.camera = camera_;
  obs.frame = static_cast<std::int64_t>(observations_.size());
  obs.device_time = frame.device_time;
  obs.detection = detectBoard(board_, frame.colour);
  const BoardFrameObservation* previous = observations_.empty() ? nullptr : &observations_.back();
  if (obs.detection.usable()) {
    ++frames_with_board_;
    if (previous && previous->detection.usable())
      obs.motion_px = cornerMotion(previous->detection, obs.detection);
    obs.steady = stills_ || (obs.motion_px >= 0 && obs.motion_px < kSteadyMotionPx);
    if (!obs.steady) {
      ++frames_moving_;
    } else {
      const ViewPose view = describeView(obs.detection, image_size_);
      if (nearCopy(view)) {
        ++frames_repeated_;
      } else {
        obs.kept = true;
        kept_poses_.push_back(view);
        coverage_.add(view);
        kept_.push_back({name, obs.detection});
        kept_pictures_.push_back(drawDetection(board_, frame.colour, obs.detection));
      }
    }
  }
  observations_.push_back(std::move(obs));
  return observations_.back();
}

}  // namespace holo::calib
