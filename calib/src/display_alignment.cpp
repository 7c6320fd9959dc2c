#include "holo/calib/display_alignment.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::calib {

namespace {

cv::Point2d centreOf(cv::Size view) {
  return {0.5 * (view.width - 1), 0.5 * (view.height - 1)};
}

double rmsResidual(const cv::Matx23d& A, const std::vector<cv::Point2f>& from,
                   const std::vector<cv::Point2f>& to) {
  double sum = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const cv::Vec3d p(from[i].x, from[i].y, 1.0);
    const cv::Vec2d q = A * p;
    sum += std::pow(q[0] - to[i].x, 2) + std::pow(q[1] - to[i].y, 2);
  }
  return std::sqrt(sum / static_cast<double>(from.size()));
}

}  // namespace

cv::Matx23d faceTransform(const FaceAlignment& a, cv::Size view) {
  const cv::Point2d c = centreOf(view);
  const double t = a.rotation_deg * CV_PI / 180.0;
  const double m = a.mirror ? -1.0 : 1.0;
  // Counter-clockwise on a y-down screen.
  const cv::Matx22d R(std::cos(t), std::sin(t), -std::sin(t), std::cos(t));
  const cv::Matx22d L = R * cv::Matx22d(a.scale * m, 0, 0, a.scale);
  const cv::Vec2d shift = cv::Vec2d(c.x + a.offset_px.x, c.y + a.offset_px.y) - L * cv::Vec2d(c.x, c.y);
  return {L(0, 0), L(0, 1), shift[0], L(1, 0), L(1, 1), shift[1]};
}

std::vector<cv::Point2f> testPatternDots(cv::Size view) {
  std::vector<cv::Point2f> dots;
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 5; ++c)
      dots.emplace_back(static_cast<float>(view.width * (0.1 + 0.2 * c)),
                        static_cast<float>(view.height * (0.1 + 0.2 * r)));
  return dots;
}

cv::Mat drawTestPattern(cv::Size view, int face) {
  cv::Mat image(view, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::rectangle(image, {0, 0}, {view.width - 1, view.height - 1}, {255, 255, 255}, 2);
  const int radius = std::max(2, std::min(view.width, view.height) / 60);
  for (const auto& dot : testPatternDots(view))
    cv::circle(image, dot, radius, {255, 255, 255}, cv::FILLED, cv::LINE_AA);
  const cv::Point2d c = centreOf(view);
  const int arrow = view.height / 4;
  cv::arrowedLine(image, cv::Point(static_cast<int>(c.x), static_cast<int>(c.y) + arrow / 2),
                  cv::Point(static_cast<int>(c.x), static_cast<int>(c.y) - arrow / 2), {0, 200, 255}, 3,
                  cv::LINE_AA, 0, 0.3);
  cv::putText(image, "face " + std::to_string(face) + "  UP", {view.width / 20, view.height / 12},
              cv::FONT_HERSHEY_SIMPLEX, view.height / 400.0, {0, 255, 0}, 2, cv::LINE_AA);
  return image;
}

FaceFit estimateFaceAlignment(const std::vector<cv::Point2f>& pattern,
                              const std::vector<cv::Point2f>& observed, cv::Size view,
                              const std::string& source) {
  if (pattern.size() != observed.size() || pattern.size() < 3)
    throw InputError(source, "points", "at least 3 observed dots, one per pattern dot",
                     std::to_string(observed.size()) + " for " + std::to_string(pattern.size()));
  for (const auto& p : observed)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      throw InputError(source, "points", "finite pixel positions");
  const cv::Point2d c = centreOf(view);
  FaceFit best;
  best.residual_px = std::numeric_limits<double>::infinity();
  for (const bool mirror : {false, true}) {
    std::vector<cv::Point2f> from = pattern;
    if (mirror)
      for (auto& p : from) p.x = static_cast<float>(2 * c.x - p.x);
    // Least squares over all dots (no RANSAC: every dot is a deliberate correspondence).
    const cv::Mat S = cv::estimateAffinePartial2D(from, observed, cv::noArray(), cv::LMEDS);
    if (S.empty()) continue;
    const cv::Matx23d A(S);
    const double scale = std::hypot(A(0, 0), A(1, 0));
    FaceAlignment a;
    a.mirror = mirror;
    a.scale = static_cast<float>(scale);
    a.rotation_deg = static_cast<float>(std::atan2(-A(1, 0), A(0, 0)) * 180.0 / CV_PI);
    const cv::Vec2d centre_to = A * cv::Vec3d(c.x, c.y, 1.0);
    a.offset_px = {static_cast<float>(centre_to[0] - c.x), static_cast<float>(centre_to[1] - c.y)};
    const double residual = rmsResidual(faceTransform(a, view), pattern, observed);
    if (residual < best.residual_px) best = {a, residual};
  }
  if (!std::isfinite(best.residual_px))
    throw InputError(source, "points", "dots in a non-degenerate layout", "no fit");
  return best;
}

}  // namespace holo::calib
