#include "holo/calib/edge_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/pose.hpp"
#include "holo/core/error.hpp"

namespace holo::calib {

namespace {

// Canny on the lightly smoothed grey image: the printed edges are strong steps, sensor noise
// and the hall's texture mostly stay below the thresholds.
constexpr double kCannyLow = 40.0;
constexpr double kCannyHigh = 100.0;
constexpr double kSmoothingSigma = 1.0;
constexpr int kIterations = 40;
// The alignment first pulls with a wide reach (a pose a centimetre off puts a near target's edges
// 10-20 px away), then with the figure's own truncation, which ignores edges that are not the target's.
constexpr double kWideReachPx = 3.0 * kEdgeTruncationPx;
constexpr double kDerivativeStep = 1e-6;  // radians and metres, for the numeric Jacobian

struct Projector {
  cv::Matx33d K;
  cv::Vec<double, 5> distortion;
  cv::Size size;

  // Pixels of `points` (world) seen from T_camera_world; `valid` false behind the camera.
  void project(const std::vector<cv::Point3d>& points, const cv::Matx44d& T_camera_world,
               std::vector<cv::Point2d>& pixels, std::vector<bool>& valid) const {
    std::vector<cv::Point3d> in_camera(points.size());
    valid.assign(points.size(), false);
    for (std::size_t i = 0; i < points.size(); ++i) {
      in_camera[i] = transform(T_camera_world, points[i]);
      valid[i] = in_camera[i].z > 1e-3;
    }
    cv::projectPoints(in_camera, cv::Vec3d::all(0.0), cv::Vec3d::all(0.0), K, distortion, pixels);
  }
};

Projector projectorOf(const CameraModel& camera) {
  const Intrinsics& k = camera.intrinsics();
  return {
      cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
      cv::Vec<double, 5>(k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3], k.distortion[4]),
      cv::Size(k.width, k.height)};
}

double bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, image.cols - 2);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, image.rows - 2);
  const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

bool inside(const cv::Size& size, const cv::Point2d& p) {
  return p.x >= 0.0 && p.y >= 0.0 && p.x <= size.width - 1.0 && p.y <= size.height - 1.0;
}

// Truncated distance to the nearest edge at each sample, and its image gradient (zero where
// truncated or unseen: such a sample pulls the pose nowhere).
struct Residuals {
  std::vector<double> distance;
  std::vector<cv::Point2d> gradient;
  int seen = 0;
  double cost() const {
    double sum = 0.0;
    for (const double d : distance) sum += d * d;
    return sum;
  }
  double mean(double truncation) const {
    double sum = 0.0;
    for (const double d : distance) sum += std::min(d, truncation);
    return distance.empty() ? truncation : sum / static_cast<double>(distance.size());
  }
};

Residuals residuals(const cv::Mat& distance, const std::vector<cv::Point2d>& pixels,
                    const std::vector<bool>& valid, double truncation) {
  Residuals out;
  out.distance.assign(pixels.size(), truncation);
  out.gradient.assign(pixels.size(), cv::Point2d(0, 0));
  const cv::Size size = distance.size();
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (!valid[i] || !inside(size, pixels[i])) continue;
    ++out.seen;
    const double x = pixels[i].x, y = pixels[i].y;
    const double d = bilinear(distance, x, y);
    if (d >= truncation) continue;
    out.distance[i] = d;
    out.gradient[i] = {bilinear(distance, x + 0.5, y) - bilinear(distance, x - 0.5, y),
                       bilinear(distance, x, y + 0.5) - bilinear(distance, x, y - 0.5)};
  }
  return out;
}

// The camera moved by `delta` (rotation vector, then translation, in the camera's own frame).
cv::Matx44d moved(const cv::Matx44d& T_world_camera, const cv::Vec6d& delta) {
  return T_world_camera * poseFromRt({delta[0], delta[1], delta[2]}, {delta[3], delta[4], delta[5]});
}

std::vector<cv::Point3d> samplePoints(const Projector& projector, const cv::Matx44d& T_camera_world,
                                      const std::vector<EdgeSegment>& segments) {
  std::vector<cv::Point3d> points;
  for (const EdgeSegment& s : segments) {
    std::vector<cv::Point2d> ends;
    std::vector<bool> valid;
    projector.project({s.a, s.b}, T_camera_world, ends, valid);
    // An edge behind the camera still gets samples: they count as unseen.
    const double length = valid[0] && valid[1] ? cv::norm(ends[1] - ends[0]) : 128.0;
    const int n = std::max(2, static_cast<int>(std::ceil(std::min(length, 4096.0) / kEdgeSampleSpacingPx)));
    for (int k = 0; k < n; ++k) {
      const double t = (k + 0.5) / n;
      points.push_back(s.a + t * (s.b - s.a));
    }
  }
  return points;
}

cv::Mat edgeImage(const cv::Mat& colour) {
  cv::Mat grey;
  if (colour.channels() == 3)
    cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  else
    grey = colour;
  cv::GaussianBlur(grey, grey, cv::Size(0, 0), kSmoothingSigma);
  cv::Mat edges;
  cv::Canny(grey, edges, kCannyLow, kCannyHigh, 3, true);
  return edges;
}

}  // namespace

EdgeAlignment measureEdgeAlignment(const cv::Mat& colour, const CameraModel& camera,
                                   const std::vector<EdgeSegment>& segments, const std::string& what) {
  const Projector projector = projectorOf(camera);
  if (colour.size() != projector.size || colour.depth() != CV_8U ||
      (colour.channels() != 1 && colour.channels() != 3))
    throw InputError(what, "colour image",
                     "8-bit BGR or grey of the calibrated size " + std::to_string(projector.size.width) +
                         "x" + std::to_string(projector.size.height),
                     std::to_string(colour.cols) + "x" + std::to_string(colour.rows) + ", " +
                         std::to_string(colour.channels()) + " channels");
  if (segments.empty()) throw InputError(what, "edges", "at least one edge of known geometry", "none");

  cv::Mat not_edges = edgeImage(colour) == 0, distance;
  cv::distanceTransform(not_edges, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

  const cv::Matx44d T_world_camera = toMatx(camera.T_world_camera());
  const std::vector<cv::Point3d> points = samplePoints(projector, rigidInverse(T_world_camera), segments);
  std::vector<cv::Point2d> pixels;
  std::vector<bool> valid;
  double truncation = kEdgeTruncationPx;
  const auto evaluate = [&](const cv::Matx44d& T_wc) {
    projector.project(points, rigidInverse(T_wc), pixels, valid);
    return residuals(distance, pixels, valid, truncation);
  };

  EdgeAlignment out;
  out.samples = static_cast<int>(points.size());
  Residuals current = evaluate(T_world_camera);
  out.chamfer_px = current.mean(kEdgeTruncationPx);
  out.seen_fraction = static_cast<double>(current.seen) / std::max(1, out.samples);

  // Levenberg-Marquardt over the camera's six degrees of freedom, wide reach first.
  cv::Matx44d T = T_world_camera;
  for (const double reach : {kWideReachPx, kEdgeTruncationPx}) {
    truncation = reach;
    current = evaluate(T);
    double lambda = 1e-3;
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      const std::vector<cv::Point2d> base = pixels;
      std::vector<cv::Vec6d> jacobian(points.size(), cv::Vec6d::all(0.0));
      for (int p = 0; p < 6; ++p) {
        cv::Vec6d step = cv::Vec6d::all(0.0);
        step[p] = kDerivativeStep;
        std::vector<cv::Point2d> shifted;
        std::vector<bool> shifted_valid;
        projector.project(points, rigidInverse(moved(T, step)), shifted, shifted_valid);
        for (std::size_t i = 0; i < points.size(); ++i)
          jacobian[i][p] = current.gradient[i].dot((shifted[i] - base[i]) / kDerivativeStep);
      }
      cv::Matx66d JtJ = cv::Matx66d::zeros();
      cv::Vec6d Jtr = cv::Vec6d::all(0.0);
      for (std::size_t i = 0; i < points.size(); ++i) {
        JtJ += jacobian[i] * jacobian[i].t();
        Jtr += jacobian[i] * current.distance[i];
      }
      bool improved = false;
      for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
        cv::Matx66d A = JtJ;
        for (int d = 0; d < 6; ++d) A(d, d) += lambda * std::max(JtJ(d, d), 1e-9);
        cv::Vec6d delta;
        if (!cv::solve(A, -Jtr, delta, cv::DECOMP_CHOLESKY)) break;
        const cv::Matx44d candidate = moved(T, delta);
        Residuals trial = evaluate(candidate);
        if (trial.cost() < current.cost()) {
          T = candidate;
          current = std::move(trial);
          lambda = std::max(lambda / 3.0, 1e-7);
          improved = true;
        } else {
          lambda *= 4.0;
        }
      }
      if (!improved) break;
    }
  }
  out.chamfer_aligned_px = current.mean(kEdgeTruncationPx);
  out.T_world_camera_aligned = T;
  out.position_error_mm = 1000.0 * translationError(T, T_world_camera);
  out.rotation_error_deg = rotationErrorDeg(T, T_world_camera);
  return out;
}

cv::Mat drawEdgeAlignment(const cv::Mat& colour, const CameraModel& camera,
                          const std::vector<EdgeSegment>& segments, const EdgeAlignment& alignment) {
  cv::Mat picture;
  if (colour.channels() == 1)
    cv::cvtColor(colour, picture, cv::COLOR_GRAY2BGR);
  else
    picture = colour.clone();
  picture *= 0.6;
  picture.setTo(cv::Scalar(255, 128, 0), edgeImage(colour));
  const Projector projector = projectorOf(camera);
  const auto draw = [&](const cv::Matx44d& T_world_camera, const cv::Scalar& colour_bgr) {
    const std::vector<cv::Point3d> points = samplePoints(projector, rigidInverse(T_world_camera), segments);
    std::vector<cv::Point2d> pixels;
    std::vector<bool> valid;
    projector.project(points, rigidInverse(T_world_camera), pixels, valid);
    for (std::size_t i = 0; i < pixels.size(); ++i)
      if (valid[i] && inside(picture.size(), pixels[i]))
        cv::circle(picture, cv::Point(cvRound(pixels[i].x), cvRound(pixels[i].y)), 1, colour_bgr, cv::FILLED);
  };
  draw(alignment.T_world_camera_aligned, cv::Scalar(255, 0, 255));
  draw(toMatx(camera.T_world_camera()), cv::Scalar(0, 255, 0));
  return picture;
}

}  // namespace holo::calib
