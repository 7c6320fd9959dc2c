// What makes a real installation's cameras disagree with each other and with the truth, for a
// recording of the simulated museum to be calibrated (`holopyramid simulate --calibration`):
// each camera's colour and depth come from two devices, the depth device's frames lag the
// colour device's by `depth_skew_s` and its nominal depth scale is off (true depth = (1 +
// depth_scale_error) x nominal depth), and every colour device has its own white balance and
// exposure (a per-channel linear response, seeded).
//
// Units: seconds, linear RGB multipliers; depth in metres (CV_32FC1, 0 = invalid).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "holo/core/math.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::sim {

struct DeviceErrors {
  double depth_skew_s = 0.015;      // depth frame time - colour frame time, >= 0
  double depth_scale_error = 0.02;  // true / nominal depth - 1; > -0.5
  // Per-channel responses are drawn in [min_response, max_response]: below 1, since a brighter
  // response would clip the board's white the colour matching measures (the sensor saturates).
  float min_response = 0.75f;
  float max_response = 0.95f;
  std::uint64_t seed = 1;
};

// Camera `camera`'s colour response: linear RGB multipliers in [min_response, max_response], seeded by
// (errors.seed, camera); the same on every call.
vec3 colourResponse(const DeviceErrors& errors, int camera);

// The gains that match the cameras to each other the way the colour-matching step defines them
// (calib/colour_gains.hpp: every camera to the mean contrast over cameras and channels):
// mean response / response, per channel.
std::vector<vec3> matchingGains(const DeviceErrors& errors, int cameras);

// The metres per raw unit a depth device with nominal `nominal_metres_per_unit` really has.
double trueMetresPerUnit(const DeviceErrors& errors, double nominal_metres_per_unit);

// Applies camera `camera`'s colour response to `frame.colour` (8-bit sRGB BGR, decoded, scaled,
// encoded again) and the depth scale error to `frame.depth` (nominal = true / (1 + error)).
void applyDeviceErrors(const DeviceErrors& errors, int camera, RgbdFrame& frame);

}  // namespace holo::sim
