#include "holo/depthfilter/other_camera_witness.hpp"

#include <cmath>
#include <string>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

OtherCameraWitnesses::OtherCameraWitnesses(std::vector<CameraModel> cameras, float tolerance_m,
                                           float tolerance_z2)
    : cameras_(std::move(cameras)), tolerance_m_(tolerance_m), tolerance_z2_(tolerance_z2) {
  if (!(tolerance_m_ >= 0.001f && tolerance_m_ <= 0.5f))
    throw Error("OtherCameraWitnesses: tolerance_m must be in [0.001, 0.5], got " +
                std::to_string(tolerance_m_));
  if (!(tolerance_z2_ >= 0.0f && tolerance_z2_ <= 0.1f))
    throw Error("OtherCameraWitnesses: tolerance_z2 must be in [0, 0.1], got " +
                std::to_string(tolerance_z2_));
  plane_directions_.reserve(cameras_.size());
  for (const CameraModel& camera : cameras_) plane_directions_.push_back(camera.planeDirectionTable());
  a_from_b_.resize(cameras_.size());
  for (std::size_t b = 0; b < cameras_.size(); ++b)
    for (const CameraModel& a : cameras_)
      a_from_b_[b].push_back(a.T_camera_world() * cameras_[b].T_world_camera());
}

OtherCameraWitness OtherCameraWitnesses::witnessFor(std::span<const CrossCameraView> views,
                                                    std::size_t target) const {
  if (views.size() != cameras_.size() || target >= views.size())
    throw Error("OtherCameraWitnesses: expected " + std::to_string(cameras_.size()) +
                " views and a target among them, got " + std::to_string(views.size()) + " views, target " +
                std::to_string(target));
  for (std::size_t i = 0; i < views.size(); ++i) {
    const CrossCameraView& v = views[i];
    if (v.depth.empty()) continue;
    const cv::Size size(cameras_[i].width(), cameras_[i].height());
    if (v.depth.type() != CV_32FC1 || v.depth.size() != size || v.mask.type() != CV_8UC1 ||
        v.mask.size() != size)
      throw Error("OtherCameraWitnesses: camera " + std::to_string(i) +
                  ": expected CV_32FC1 depth and CV_8UC1 mask of " + std::to_string(size.width) + "x" +
                  std::to_string(size.height));
  }
  return OtherCameraWitness(*this, views, target);
}

Sighting OtherCameraWitness::sighting(int x, int y, float depth) const {
  const OtherCameraWitnesses& w = *witnesses_;
  const CameraModel& camera_b = w.cameras_[target_];
  if (x < 0 || y < 0 || x >= camera_b.width() || y >= camera_b.height() || !(depth > 0.0f))
    return Sighting::Unknown;
  const vec3 point_b =
      w.plane_directions_[target_][std::size_t(y) * std::size_t(camera_b.width()) + std::size_t(x)] * depth;
  bool seen = false, empty = false;
  for (std::size_t a = 0; a < views_.size(); ++a) {
    const CrossCameraView& view = views_[a];
    if (a == target_ || view.depth.empty()) continue;
    const vec3 point_a = transformPoint(w.a_from_b_[target_][a], point_b);
    if (!(point_a.z > 0.0f)) continue;
    const std::optional<vec2> pixel = w.cameras_[a].projectCamera(point_a);
    if (!pixel) continue;
    const int u = int(std::lround(pixel->x)), v = int(std::lround(pixel->y));
    if (u < 0 || v < 0 || u >= view.depth.cols || v >= view.depth.rows) continue;
    const float measured = view.depth.at<float>(v, u);
    if (!(measured > 0.0f) || !std::isfinite(measured)) continue;
    const float tolerance = w.tolerance_m_ + w.tolerance_z2_ * point_a.z * point_a.z;
    if (measured > point_a.z + tolerance)
      empty = true;
    else if (measured >= point_a.z - tolerance && view.mask.at<std::uint8_t>(v, u) != 0)
      seen = true;
  }
  if (seen == empty) return Sighting::Unknown;
  return seen ? Sighting::Seen : Sighting::Empty;
}

}  // namespace holo::depthfilter
