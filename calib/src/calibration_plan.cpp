#include "holo/calib/calibration_plan.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace holo::calib {

std::vector<cv::Matx44d> defaultBoardPlacements(const BoardSpec& board, int cameras, double base_half_width) {
  std::vector<cv::Matx44d> placements;
  const cv::Rect2d e = board.extent();
  const cv::Vec3d board_centre(e.x + e.width / 2, e.y + e.height / 2, 0);
  for (int f = 0; f < cameras; ++f) {
    const double azimuth = f * CV_PI / 2;
    const cv::Vec3d out(std::sin(azimuth), 0, std::cos(azimuth));
    // Board axes in the world: +Z away from the camera (the printed side faces it), +Y down.
    const cv::Vec3d z = out, y(0, -1, 0), x = y.cross(z);
    const cv::Matx33d upright(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]);
    cv::Matx33d lean, turn;
    cv::Rodrigues(cv::Vec3d(12.0 * CV_PI / 180, 0, 0), lean);
    cv::Rodrigues(cv::Vec3d(0, (f % 2 ? -20.0 : 20.0) * CV_PI / 180, 0), turn);
    const cv::Matx33d R = upright * lean * turn;
    const cv::Vec3d centre = (base_half_width + 0.75) * out + cv::Vec3d(0, -0.05, 0);
    const cv::Vec3d t = centre - R * board_centre;
    placements.emplace_back(R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1], R(2, 0),
                            R(2, 1), R(2, 2), t[2], 0, 0, 0, 1);
  }
  return placements;
}

bool AutoCalibrationReport::allPassed() const {
  return std::all_of(verdicts.begin(), verdicts.end(), [](const StepVerdict& v) { return v.pass; });
}

}  // namespace holo::calib
