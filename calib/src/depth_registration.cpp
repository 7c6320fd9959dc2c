#include "holo/calib/depth_registration.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::calib {

namespace {

// A depth pixel this close to the plane belongs to the board.
constexpr double kInlierDistanceM = 0.01;
constexpr int kRansacIterations = 300;
constexpr int kMinInliers = 200;

cv::Matx33d cameraMatrix(const Intrinsics& K) {
  return {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
}

cv::Vec3d transformPoint(const cv::Matx44d& T, const cv::Vec3d& p) {
  return {T(0, 0) * p[0] + T(0, 1) * p[1] + T(0, 2) * p[2] + T(0, 3),
          T(1, 0) * p[0] + T(1, 1) * p[1] + T(1, 2) * p[2] + T(1, 3),
          T(2, 0) * p[0] + T(2, 1) * p[1] + T(2, 2) * p[2] + T(2, 3)};
}

// Least-squares plane through `points` (centroid and the covariance's smallest eigenvector),
// oriented so that its distance from the origin is positive.
Plane planeThrough(const std::vector<cv::Vec3d>& points) {
  cv::Vec3d centroid(0, 0, 0);
  for (const auto& p : points) centroid += p;
  centroid *= 1.0 / static_cast<double>(points.size());
  cv::Matx33d covariance = cv::Matx33d::zeros();
  for (const auto& p : points) {
    const cv::Vec3d q = p - centroid;
    covariance += q * q.t();
  }
  cv::Mat eigenvalues, eigenvectors;
  cv::eigen(cv::Mat(covariance), eigenvalues, eigenvectors);  // descending
  Plane plane;
  plane.normal =
      cv::Vec3d(eigenvectors.at<double>(2, 0), eigenvectors.at<double>(2, 1), eigenvectors.at<double>(2, 2));
  plane.distance = plane.normal.dot(centroid);
  if (plane.distance < 0) {
    plane.normal = -plane.normal;
    plane.distance = -plane.distance;
  }
  return plane;
}

}  // namespace

std::optional<cv::Matx44d> boardPoseInCamera(const BoardDetection& detection, const Intrinsics& colour) {
  if (!detection.usable()) return std::nullopt;
  cv::Mat dist(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist.at<double>(0, i) = colour.distortion[static_cast<std::size_t>(i)];
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(detection.object_points, detection.image_points, cv::Mat(cameraMatrix(colour)), dist,
                    rvec, tvec, false, cv::SOLVEPNP_IPPE))
    return std::nullopt;
  cv::solvePnPRefineLM(detection.object_points, detection.image_points, cv::Mat(cameraMatrix(colour)), dist,
                       rvec, tvec);
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  return cv::Matx44d(R(0, 0), R(0, 1), R(0, 2), tvec[0], R(1, 0), R(1, 1), R(1, 2), tvec[1], R(2, 0), R(2, 1),
                     R(2, 2), tvec[2], 0, 0, 0, 1);
}

std::optional<Plane> boardPlaneInCamera(const BoardDetection& detection, const Intrinsics& colour) {
  const std::optional<cv::Matx44d> T = boardPoseInCamera(detection, colour);
  if (!T) return std::nullopt;
  Plane plane;
  plane.normal = cv::Vec3d((*T)(0, 2), (*T)(1, 2), (*T)(2, 2));
  plane.distance = plane.normal.dot(cv::Vec3d((*T)(0, 3), (*T)(1, 3), (*T)(2, 3)));
  if (plane.distance < 0) {
    plane.normal = -plane.normal;
    plane.distance = -plane.distance;
  }
  return plane;
}

std::optional<DepthPlaneFit> fitBoardPlaneInDepth(const cv::Mat& depth, const Intrinsics& depth_intrinsics,
                                                  const BoardSpec& board, const cv::Matx44d& T_colour_board,
                                                  const cv::Matx44d& T_depth_colour_guess, double inset) {
  if (depth.type() != CV_32FC1 || depth.cols != depth_intrinsics.width ||
      depth.rows != depth_intrinsics.height)
    throw InputError("depth registration", "depth image",
                     "CV_32FC1 metres of the depth intrinsics' size " +
                         std::to_string(depth_intrinsics.width) + "x" +
                         std::to_string(depth_intrinsics.height),
                     std::to_string(depth.cols) + "x" + std::to_string(depth.rows) + " type " +
                         std::to_string(depth.type()));
  const CameraModel camera(depth_intrinsics, mat4(1.0f));
  // The board's inner region, in the depth image.
  const cv::Rect2d e = board.extent();
  const double dx = e.width * inset, dy = e.height * inset;
  const cv::Vec3d corners[] = {{e.x + dx, e.y + dy, 0},
                               {e.x + e.width - dx, e.y + dy, 0},
                               {e.x + e.width - dx, e.y + e.height - dy, 0},
                               {e.x + dx, e.y + e.height - dy, 0}};
  const cv::Matx44d T_depth_board = T_depth_colour_guess * T_colour_board;
  std::vector<cv::Point> polygon;
  for (const cv::Vec3d& c : corners) {
    const cv::Vec3d p = transformPoint(T_depth_board, c);
    const std::optional<vec2> pixel = camera.projectCamera(
        vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])));
    if (!pixel) return std::nullopt;
    polygon.emplace_back(static_cast<int>(std::lround(pixel->x)), static_cast<int>(std::lround(pixel->y)));
  }
  cv::Mat mask(depth.size(), CV_8UC1, cv::Scalar(0));
  cv::fillConvexPoly(mask, polygon, cv::Scalar(255));
  const std::vector<vec3> directions = camera.planeDirectionTable();
  std::vector<cv::Vec3d> points;
  for (int y = 0; y < depth.rows; ++y) {
    const float* z = depth.ptr<float>(y);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < depth.cols; ++x) {
      if (!m[x] || !(z[x] > 0.0f) || !std::isfinite(z[x])) continue;
      const vec3 d = directions[static_cast<std::size_t>(y) * static_cast<std::size_t>(depth.cols) +
                                static_cast<std::size_t>(x)] *
                     z[x];
      points.emplace_back(d.x, d.y, d.z);
    }
  }
  if (static_cast<int>(points.size()) < kMinInliers) return std::nullopt;

  // RANSAC against stray pixels (the board's edge, a hand holding it), then a least-squares refit.
  cv::RNG rng(0x5eed);
  std::vector<cv::Vec3d> best;
  for (int iteration = 0; iteration < kRansacIterations; ++iteration) {
    const cv::Vec3d& a = points[static_cast<std::size_t>(rng.uniform(0, static_cast<int>(points.size())))];
    const cv::Vec3d& b = points[static_cast<std::size_t>(rng.uniform(0, static_cast<int>(points.size())))];
    const cv::Vec3d& c = points[static_cast<std::size_t>(rng.uniform(0, static_cast<int>(points.size())))];
    cv::Vec3d n = (b - a).cross(c - a);
    const double length = cv::norm(n);
    if (length < 1e-9) continue;
    n *= 1.0 / length;
    const double d = n.dot(a);
    std::vector<cv::Vec3d> inliers;
    for (const auto& p : points)
      if (std::abs(n.dot(p) - d) < kInlierDistanceM) inliers.push_back(p);
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  if (static_cast<int>(best.size()) < kMinInliers) return std::nullopt;
  DepthPlaneFit fit;
  fit.plane = planeThrough(best);
  std::vector<cv::Vec3d> inliers;
  double sum = 0.0;
  for (const auto& p : points) {
    const double r = fit.plane.normal.dot(p) - fit.plane.distance;
    if (std::abs(r) < kInlierDistanceM) {
      inliers.push_back(p);
      sum += r * r;
    }
  }
  fit.plane = planeThrough(inliers);
  fit.inliers = static_cast<int>(inliers.size());
  fit.rms_m = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, inliers.size())));
  return fit;
}

DepthRegistration fitDepthRegistration(const std::vector<PlanePair>& views, const std::string& source) {
  const int n = static_cast<int>(views.size());
  if (n < 4)
    throw InputError(source, "depth registration views",
                     "at least 4 views of the board seen in colour and depth",
                     std::to_string(n) + " (hint: show the board at several distances and tilts)");
  // Rotation: the one that turns the depth normals onto the colour normals best (Kabsch).
  cv::Matx33d H = cv::Matx33d::zeros();
  for (const PlanePair& v : views) H += v.depth.normal * v.colour.normal.t();
  cv::Mat w, u, vt;
  cv::SVD::compute(cv::Mat(H), w, u, vt);
  if (w.at<double>(1) < 0.05 * w.at<double>(0))
    throw InputError(source, "depth registration views",
                     "board normals in at least two clearly different directions",
                     "every view's board faces the same way (hint: tilt the board left-right and up-down)");
  const cv::Matx33d U(u), Vt(vt);
  const cv::Matx33d V = Vt.t();
  const double det = cv::determinant(V * U.t());
  const cv::Matx33d R = V * cv::Matx33d(1, 0, 0, 0, 1, 0, 0, 0, det < 0 ? -1.0 : 1.0) * U.t();
  // Translation and scale: n_c . t + s d_d = d_c, linear least squares.
  cv::Mat A(n, 4, CV_64F), b(n, 1, CV_64F);
  for (int i = 0; i < n; ++i) {
    const PlanePair& v = views[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) A.at<double>(i, k) = v.colour.normal[k];
    A.at<double>(i, 3) = v.depth.distance;
    b.at<double>(i) = v.colour.distance;
  }
  cv::Mat singular;
  cv::SVD::compute(A, singular, cv::SVD::NO_UV);
  if (singular.at<double>(3) < 1e-3 * singular.at<double>(0))
    throw InputError(source, "depth registration views", "views that fix the translation and the depth scale",
                     "too alike (hint: vary the board's distance and tilt it in both directions)");
  cv::Mat x;
  cv::solve(A, b, x, cv::DECOMP_SVD);
  DepthRegistration out;
  out.views = n;
  out.scale_factor = x.at<double>(3);
  out.T_colour_depth = cv::Matx44d(R(0, 0), R(0, 1), R(0, 2), x.at<double>(0), R(1, 0), R(1, 1), R(1, 2),
                                   x.at<double>(1), R(2, 0), R(2, 1), R(2, 2), x.at<double>(2), 0, 0, 0, 1);
  double distance2 = 0.0, angle2 = 0.0;
  const cv::Mat residual = A * x - b;
  for (int i = 0; i < n; ++i) {
    distance2 += residual.at<double>(i) * residual.at<double>(i);
    const cv::Vec3d turned = R * views[static_cast<std::size_t>(i)].depth.normal;
    const double c = std::clamp(turned.dot(views[static_cast<std::size_t>(i)].colour.normal), -1.0, 1.0);
    angle2 += std::acos(c) * std::acos(c);
  }
  out.rms_distance_mm = 1000.0 * std::sqrt(distance2 / n);
  out.rms_normal_deg = std::sqrt(angle2 / n) * 180.0 / CV_PI;
  return out;
}

}  // namespace holo::calib
