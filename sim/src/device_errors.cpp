#include "holo/sim/device_errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::sim {

vec3 colourResponse(const DeviceErrors& errors, int camera) {
  cv::RNG rng(errors.seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(camera) * 7919u + 17u);
  vec3 response;
  for (int c = 0; c < 3; ++c)
    response[c] = static_cast<float>(rng.uniform(errors.min_response, errors.max_response));
  return response;
}

std::vector<vec3> matchingGains(const DeviceErrors& errors, int cameras) {
  std::vector<vec3> responses;
  double sum = 0.0;
  for (int c = 0; c < cameras; ++c) {
    responses.push_back(colourResponse(errors, c));
    sum += responses.back().r + responses.back().g + responses.back().b;
  }
  const auto mean = static_cast<float>(sum / (3.0 * std::max(cameras, 1)));
  std::vector<vec3> gains;
  for (const vec3& r : responses) gains.push_back(mean / r);
  return gains;
}

double trueMetresPerUnit(const DeviceErrors& errors, double nominal_metres_per_unit) {
  return nominal_metres_per_unit * (1.0 + errors.depth_scale_error);
}

void applyDeviceErrors(const DeviceErrors& errors, int camera, RgbdFrame& frame) {
  if (!(errors.depth_scale_error > -0.5))
    throw Error("applyDeviceErrors: depth scale error must exceed -0.5");
  if (!frame.colour.empty()) {
    HOLO_ASSERT(frame.colour.type() == CV_8UC3);
    const vec3 response = colourResponse(errors, camera);
    // One table per channel (BGR order): 8-bit sRGB -> linear x response -> 8-bit sRGB.
    std::array<cv::Mat, 3> tables;
    for (int ch = 0; ch < 3; ++ch) {
      tables[static_cast<std::size_t>(ch)] = cv::Mat(1, 256, CV_8UC1);
      const float gain = response[2 - ch];
      for (int v = 0; v < 256; ++v)
        tables[static_cast<std::size_t>(ch)].at<std::uint8_t>(v) = cv::saturate_cast<std::uint8_t>(
            std::lround(255.0f * linearToSrgb(gain * srgbToLinear(static_cast<float>(v) / 255.0f))));
    }
    cv::Mat table;
    cv::merge(std::vector<cv::Mat>(tables.begin(), tables.end()), table);
    cv::Mat out;
    cv::LUT(frame.colour, table, out);
    frame.colour = out;
  }
  if (!frame.depth.empty()) {
    cv::Mat nominal;
    frame.depth.convertTo(nominal, CV_32FC1, 1.0 / (1.0 + errors.depth_scale_error));
    frame.depth = nominal;
  }
}

}  // namespace holo::sim
