#include "holo/calib/background.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/median.hpp"

namespace holo::calib {

BackgroundModel captureBackground(const std::vector<RgbdFrame>& frames, const std::string& source) {
  if (frames.empty()) throw InputError(source, "frames", "at least one frame of the empty hall", "none");
  const cv::Size size = frames.front().colour.size();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const RgbdFrame& f = frames[i];
    const std::string field = "frame " + std::to_string(i);
    if (f.colour.type() != CV_8UC3 || f.colour.size() != size)
      throw InputError(source, field,
                       "CV_8UC3 colour of " + std::to_string(size.width) + "x" + std::to_string(size.height));
    if (f.depth.type() != CV_32FC1 || f.depth.size() != size)
      throw InputError(source, field, "CV_32FC1 depth of the colour's size");
  }
  const int n = static_cast<int>(frames.size());
  BackgroundModel model;
  model.frames = n;
  model.colour.create(size, CV_8UC3);
  model.depth.create(size, CV_32FC1);
  model.invalid_count.create(size, CV_16UC1);
  std::vector<std::uint8_t> channel(static_cast<std::size_t>(n)), grey(static_cast<std::size_t>(n));
  std::vector<float> depths;
  depths.reserve(static_cast<std::size_t>(n));
  long long invalid_pixels = 0;
  double mad_sum = 0;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      cv::Vec3b out;
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < n; ++k)
          channel[static_cast<std::size_t>(k)] =
              frames[static_cast<std::size_t>(k)].colour.at<cv::Vec3b>(y, x)[c];
        out[c] = medianInPlace(channel);
      }
      model.colour.at<cv::Vec3b>(y, x) = out;
      // Grey level spread: how much the scene moved or flickered while capturing.
      for (int k = 0; k < n; ++k) {
        const cv::Vec3b& p = frames[static_cast<std::size_t>(k)].colour.at<cv::Vec3b>(y, x);
        grey[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>((p[0] + 2 * p[1] + p[2] + 2) / 4);
      }
      const int grey_median = medianInPlace(grey);
      for (auto& g : grey) g = static_cast<std::uint8_t>(std::abs(static_cast<int>(g) - grey_median));
      mad_sum += medianInPlace(grey);

      depths.clear();
      for (int k = 0; k < n; ++k) {
        const float d = frames[static_cast<std::size_t>(k)].depth.at<float>(y, x);
        if (std::isfinite(d) && d > 0.0f) depths.push_back(d);
      }
      const int invalid = n - static_cast<int>(depths.size());
      model.invalid_samples += invalid;
      model.invalid_count.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(std::min(invalid, 65535));
      // A pixel mostly without depth stays invalid: a median of a few lucky samples would be
      // dominated by flying pixels and noise.
      const bool valid = 2 * static_cast<int>(depths.size()) >= n && !depths.empty();
      model.depth.at<float>(y, x) = valid ? medianInPlace(depths) : 0.0f;
      invalid_pixels += valid ? 0 : 1;
    }
  const double pixels = static_cast<double>(size.area());
  model.invalid_fraction = pixels > 0 ? static_cast<double>(invalid_pixels) / pixels : 0.0;
  model.colour_mad = pixels > 0 ? mad_sum / pixels : 0.0;
  return model;
}

}  // namespace holo::calib
