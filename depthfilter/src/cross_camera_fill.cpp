#include "holo/depthfilter/cross_camera_fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {
namespace {

bool measured(float d) {
  return d > 0.0f && std::isfinite(d);
}

float tolerance(const CrossCameraFillConfig& c, float z) {
  return c.tolerance_m + c.tolerance_z2 * z * z;
}

// A point one camera sends: its camera-frame position and its surface's normal there, turned
// towards that camera.
struct SourcePoint {
  vec3 position;
  vec3 normal;
};

// The interior foreground pixels of one view with measured depth: all four neighbours measured on
// the same surface, so the point is not a silhouette's mixed pixel and its normal is known.
std::vector<SourcePoint> sourcePoints(const CrossCameraView& view, const std::vector<vec3>& directions,
                                      const CrossCameraFillConfig& config) {
  std::vector<SourcePoint> points;
  if (view.depth.empty()) return points;
  const cv::Rect box = cv::boundingRect(view.mask);
  const int cols = view.depth.cols;
  const int y_end = std::min(box.y + box.height, view.depth.rows - 1);
  const int x_end = std::min(box.x + box.width, cols - 1);
  for (int y = std::max(box.y, 1); y < y_end; ++y) {
    const std::uint8_t* m = view.mask.ptr<std::uint8_t>(y);
    const float* up = view.depth.ptr<float>(y - 1);
    const float* row = view.depth.ptr<float>(y);
    const float* down = view.depth.ptr<float>(y + 1);
    for (int x = std::max(box.x, 1); x < x_end; ++x) {
      const float d = row[x];
      if (!m[x] || !measured(d)) continue;
      const float tol = tolerance(config, d);
      const float l = row[x - 1], r = row[x + 1], u = up[x], dn = down[x];
      if (!(std::abs(l - d) <= tol && std::abs(r - d) <= tol && std::abs(u - d) <= tol &&
            std::abs(dn - d) <= tol))
        continue;  // NaN differences fail too: a neighbour without depth
      const std::size_t i = std::size_t(y) * std::size_t(cols) + std::size_t(x);
      const std::size_t w = std::size_t(cols);
      const vec3 p = directions[i] * d;
      const vec3 along_x = directions[i + 1] * r - directions[i - 1] * l;
      const vec3 along_y = directions[i + w] * dn - directions[i - w] * u;
      vec3 normal = glm::cross(along_x, along_y);
      if (glm::dot(normal, p) > 0.0f) normal = -normal;
      points.push_back({p, normal});
    }
  }
  return points;
}

void checkView(const CrossCameraView& view, const CameraModel& camera, std::size_t index) {
  if (view.depth.empty()) return;
  const cv::Size size(camera.width(), camera.height());
  if (view.depth.type() != CV_32FC1 || view.depth.size() != size || view.mask.type() != CV_8UC1 ||
      view.mask.size() != size ||
      (!view.background_depth.empty() &&
       (view.background_depth.type() != CV_32FC1 || view.background_depth.size() != size)))
    throw Error("CrossCameraFill: camera " + std::to_string(index) +
                ": expected CV_32FC1 depth, CV_8UC1 mask " + "and CV_32FC1 background depth (or none) of " +
                std::to_string(size.width) + "x" + std::to_string(size.height));
}

}  // namespace

CrossCameraFill::CrossCameraFill(std::vector<CameraModel> cameras, CrossCameraFillConfig config)
    : cameras_(std::move(cameras)), config_(config) {
  const auto refuse = [](const std::string& field, const std::string& range, const std::string& got) {
    throw Error("CrossCameraFill: " + field + " must be in " + range + ", got " + got);
  };
  if (!(config_.tolerance_m >= 0.001f && config_.tolerance_m <= 0.5f))
    refuse("tolerance_m", "[0.001, 0.5]", std::to_string(config_.tolerance_m));
  if (!(config_.tolerance_z2 >= 0.0f && config_.tolerance_z2 <= 0.1f))
    refuse("tolerance_z2", "[0, 0.1]", std::to_string(config_.tolerance_z2));
  if (config_.visibility_radius_px < 0 || config_.visibility_radius_px > 8)
    refuse("visibility_radius_px", "[0, 8]", std::to_string(config_.visibility_radius_px));
  if (config_.max_splat_px < 1 || config_.max_splat_px > 8)
    refuse("max_splat_px", "[1, 8]", std::to_string(config_.max_splat_px));
  plane_directions_.reserve(cameras_.size());
  for (const CameraModel& camera : cameras_) plane_directions_.push_back(camera.planeDirectionTable());
}

std::vector<cv::Mat> CrossCameraFill::apply(std::span<CrossCameraView> views,
                                            std::vector<CrossCameraCounts>* counts) const {
  if (views.size() != cameras_.size())
    throw Error("CrossCameraFill: expected " + std::to_string(cameras_.size()) + " views, got " +
                std::to_string(views.size()));
  for (std::size_t i = 0; i < views.size(); ++i) checkView(views[i], cameras_[i], i);
  if (counts) counts->assign(views.size(), {});
  std::vector<cv::Mat> out(views.size());
  for (std::size_t i = 0; i < views.size(); ++i) out[i] = views[i].depth;
  if (!config_.enabled || views.size() < 2) return out;

  // Every source is read before any mask grows: what one camera receives is not passed on.
  std::vector<std::vector<SourcePoint>> sources(views.size());
  for (std::size_t a = 0; a < views.size(); ++a)
    sources[a] = sourcePoints(views[a], plane_directions_[a], config_);

  constexpr float kFar = std::numeric_limits<float>::infinity();
  constexpr float kMinFacingCosine = 0.1f;  // grazing surfaces are where depth is least sure
  cv::Mat nearest, front_sum, front_count;
  for (std::size_t b = 0; b < views.size(); ++b) {
    CrossCameraView& target = views[b];
    if (target.depth.empty()) continue;
    const CameraModel& camera_b = cameras_[b];
    const int cols = camera_b.width(), rows = camera_b.height();
    // Every source point B can face, as B's pixel square and depth.
    struct Splat {
      int x0, y0, size;
      float z;
    };
    std::vector<Splat> splats;
    for (std::size_t a = 0; a < views.size(); ++a) {
      if (a == b || sources[a].empty()) continue;
      const CameraModel& camera_a = cameras_[a];
      const mat4 b_from_a = camera_b.T_camera_world() * camera_a.T_world_camera();
      const vec3 b_centre_in_a = transformPoint(camera_a.T_camera_world(), camera_b.position());
      const float footprint = camera_b.intrinsics().fx / camera_a.intrinsics().fx;
      for (const SourcePoint& s : sources[a]) {
        const vec3 to_b = b_centre_in_a - s.position;
        if (glm::dot(s.normal, to_b) <= kMinFacingCosine * glm::length(s.normal) * glm::length(to_b))
          continue;
        const vec3 p = transformPoint(b_from_a, s.position);
        if (!(p.z > 0.0f)) continue;
        const std::optional<vec2> pixel = camera_b.projectCamera(p);
        if (!pixel) continue;
        const int size = std::clamp(int(std::ceil(footprint * s.position.z / p.z)), 1, config_.max_splat_px);
        const int x0 = int(std::lround(pixel->x - 0.5f * float(size - 1)));
        const int y0 = int(std::lround(pixel->y - 0.5f * float(size - 1)));
        if (x0 + size <= 0 || y0 + size <= 0 || x0 >= cols || y0 >= rows) continue;
        splats.push_back({x0, y0, size, p.z});
      }
    }
    if (splats.empty()) continue;
    // The nearest surface per pixel (a z-buffer), then the mean of the points on it: one
    // source's noise and a splat's offset along a slope average out.
    nearest.create(rows, cols, CV_32FC1);
    nearest.setTo(kFar);
    int x_min = cols, x_max = -1, y_min = rows, y_max = -1;
    const auto for_each_pixel = [&](const Splat& s, const auto& visit) {
      for (int y = std::max(s.y0, 0); y < std::min(s.y0 + s.size, rows); ++y)
        for (int x = std::max(s.x0, 0); x < std::min(s.x0 + s.size, cols); ++x) visit(x, y);
    };
    for (const Splat& s : splats)
      for_each_pixel(s, [&](int x, int y) {
        float& z = nearest.at<float>(y, x);
        z = std::min(z, s.z);
        x_min = std::min(x_min, x), x_max = std::max(x_max, x);
        y_min = std::min(y_min, y), y_max = std::max(y_max, y);
      });
    front_sum.create(rows, cols, CV_32FC1);
    front_count.create(rows, cols, CV_32FC1);
    const cv::Rect box(x_min, y_min, x_max - x_min + 1, y_max - y_min + 1);
    front_sum(box).setTo(0.0f);
    front_count(box).setTo(0.0f);
    for (const Splat& s : splats)
      for_each_pixel(s, [&](int x, int y) {
        const float z = nearest.at<float>(y, x);
        if (s.z > z + tolerance(config_, z)) return;
        front_sum.at<float>(y, x) += s.z;
        front_count.at<float>(y, x) += 1.0f;
      });
    for (int y = y_min; y <= y_max; ++y) {
      float* z = nearest.ptr<float>(y);
      const float* sum = front_sum.ptr<float>(y);
      const float* count = front_count.ptr<float>(y);
      for (int x = x_min; x <= x_max; ++x)
        if (count[x] > 0.0f) z[x] = sum[x] / count[x];
    }

    cv::Mat filled;
    CrossCameraCounts count;
    const int r = config_.visibility_radius_px;
    for (int y = y_min; y <= y_max; ++y) {
      const float* z = nearest.ptr<float>(y);
      const float* own = target.depth.ptr<float>(y);
      const float* background =
          target.background_depth.empty() ? nullptr : target.background_depth.ptr<float>(y);
      std::uint8_t* mask = target.mask.ptr<std::uint8_t>(y);
      for (int x = x_min; x <= x_max; ++x) {
        const float fill = z[x];
        if (fill == kFar) continue;
        const float tol = tolerance(config_, fill);
        if (measured(own[x])) {
          const bool before_hall = !background || !(background[x] > 0.0f) ||
                                   own[x] < background[x] - tolerance(config_, background[x]);
          if (config_.confirm_measured && !mask[x] && std::abs(own[x] - fill) <= tol && before_hall) {
            mask[x] = 255;
            ++count.confirmed;
          }
          continue;
        }
        if (background && background[x] > 0.0f && fill > background[x] - tolerance(config_, background[x]))
          continue;  // at or behind the hall's own surface: a wall hides it
        bool hidden = false;
        for (int v = std::max(y - r, 0); v <= std::min(y + r, rows - 1) && !hidden; ++v) {
          const float* near_row = target.depth.ptr<float>(v);
          for (int u = std::max(x - r, 0); u <= std::min(x + r, cols - 1); ++u)
            if (measured(near_row[u]) && near_row[u] < fill - tol) {
              hidden = true;
              break;
            }
        }
        if (hidden) continue;
        if (filled.empty()) filled = target.depth.clone();
        filled.at<float>(y, x) = fill;
        mask[x] = 255;
        ++count.filled;
      }
    }
    if (!filled.empty()) out[b] = filled;
    if (counts) (*counts)[b] = count;
  }
  return out;
}

}  // namespace holo::depthfilter
