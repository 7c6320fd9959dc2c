// Statistics of one depth frame, the figures a real depth camera is characterised by: how many
// pixels have no depth, where those holes are (beside depth edges, on people), how large they
// are, and how noisy the valid depth is at 1, 2 and 4 m. The same function measures real frames
// (TUM RGB-D) and simulated ones, so the sensor profiles can be fitted to and checked against
// real cameras (docs/sim.md, "Sensor profiles").
//
// Definitions (pixels; depth CV_32FC1 metres, 0 = hole):
//   * depth edge: both pixels of a jump of more than 0.05 m + 5% of the nearer depth between
//     consecutive valid pixels of a row or column, up to kMaxGap holes apart: a hole does not
//     hide the edge it sits on (the projector's shadow beside a person is beside an edge);
//   * edge hole: a hole within kEdgeRadius pixels (Chebyshev) of a depth edge;
//   * hole sizes: 8-connected components of holes; the shares are of all hole pixels;
//   * noise at depth Z: the median over 7 x 7 windows (every 4th pixel, all 49 pixels valid, no
//     depth edge, mean depth within 20% of Z) of the RMS residual of a least-squares plane
//     z = a + b u + c v, corrected for the 3 fitted parameters (x sqrt(49 / 46)). A flat patch
//     gives the sensor's noise including its quantisation; curved patches add a little.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace holo::sim {

inline constexpr int kEdgeRadius = 3;
inline constexpr int kMaxGap = 32;
inline constexpr std::array<float, 3> kNoiseDepths = {1.0f, 2.0f, 4.0f};
// Upper bounds of the hole-size classes (pixels): 1, 2-10, 11-100, 101-1000, more.
inline constexpr std::array<int, 4> kHoleSizeBounds = {1, 10, 100, 1000};

struct DepthStatistics {
  long long pixels = 0;
  double hole_fraction = 0;          // holes / pixels
  double edge_hole_share = 0;        // edge holes / holes
  double person_hole_fraction = -1;  // holes on the person mask / its pixels; < 0 without a mask
  double other_hole_fraction = -1;   // holes off the mask / its pixels; < 0 without a mask
  // Share of hole pixels in components of size <= kHoleSizeBounds[i], the last one above them.
  std::array<double, kHoleSizeBounds.size() + 1> hole_size_share{};
  int hole_components = 0;
  // Noise (metres) at kNoiseDepths; < 0 where fewer than kMinNoiseWindows windows qualified.
  std::array<double, kNoiseDepths.size()> noise{};
  std::array<int, kNoiseDepths.size()> noise_windows{};
  double median_depth = 0;  // of the valid pixels
};

inline constexpr int kMinNoiseWindows = 30;

// depth: CV_32FC1 metres, 0 = no depth. person: empty, or CV_8UC1 of the same size, nonzero on
// people (the hole fractions on and off it are then measured).
DepthStatistics measureDepthStatistics(const cv::Mat& depth, const cv::Mat& person = {});
// The statistics of several frames (e.g. a rig's cameras) pooled, as if they were one frame.
// persons: empty, or one mask (possibly empty) per frame.
DepthStatistics measureDepthStatistics(const std::vector<cv::Mat>& depths,
                                       const std::vector<cv::Mat>& persons);

// A 16-bit depth PNG (TUM RGB-D: `units_per_metre` 5000) as CV_32FC1 metres. Throws InputError
// naming the file for a missing or unreadable file or one that is not 16-bit single channel.
cv::Mat loadDepthPng(const std::string& path, double units_per_metre);

// One line per figure, for logs and docs.
std::string describe(const DepthStatistics& s);

}  // namespace holo::sim
