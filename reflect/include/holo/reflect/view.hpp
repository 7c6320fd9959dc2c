// Cameras for face views: a pinhole looking at the relic from a visitor's eye, as each pyramid
// face shows it. Units: metres, degrees only where the name says so. Face f in 0..3 faces +Z,
// +X, -Z, -X (azimuth f * 90 degrees, as sim/museum.hpp); its default eye is a standing visitor
// kDefaultEyeDistance from the relic's vertical axis at kDefaultEyeHeight above the floor.
#pragma once

#include "holo/core/camera_model.hpp"

namespace holo::reflect {

inline constexpr float kDefaultEyeDistance = 1.2f;  // metres from the relic axis, horizontally
inline constexpr float kDefaultEyeHeight = 1.6f;    // metres above the floor
inline constexpr float kDefaultFovDeg = 30.0f;      // vertical field of view

// Unit horizontal direction from the relic towards face f's viewer.
vec3 faceDirection(int face);
// Default eye of face f for a floor at floor_y, looking at the relic's bounding-box centre.
vec3 defaultFaceEye(int face, const Bounds3& relic_bounds, float floor_y);
// Pinhole camera at `eye` looking at `target` (OpenCV axes), square pixels, vertical fov.
CameraModel lookAtCamera(const vec3& eye, const vec3& target, float vfov_deg, int width, int height);
// The smallest vertical fov (degrees, with a 10% margin) that frames the relic's bounding
// sphere from `eye`; kDefaultFovDeg when the bounds are empty.
float framingFovDeg(const vec3& eye, const Bounds3& relic_bounds);

// Primary ray through a (sub)pixel position: fast exact pinhole path when the camera has no
// distortion, CameraModel::ray otherwise.
Ray primaryRay(const CameraModel& camera, const vec2& pixel);

}  // namespace holo::reflect
