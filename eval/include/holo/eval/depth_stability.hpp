// Depth quality without ground truth: what a real recording (or a simulated one treated as real)
// tells about the sensor and the depth filter when nobody knows the true depth
// (docs/depthfilter.md, "Real recordings"). Per camera, frame by frame, from the sensor's depth,
// the foreground mask and the filter's output (0 outside the mask):
//   * hole flicker: of the pixels that are foreground in two consecutive frames, the share whose
//     depth switches between valid and hole; for the raw depth and for the filter's output. On
//     the static background (background in both frames), the raw sensor's own flicker;
//   * temporal noise of the static background: per pixel, the standard deviation of the raw depth
//     over the frames where the pixel is background and valid (at least min_background_samples of
//     them); the median over those pixels, overall and for pixels near 1, 2 and 4 m (within 20%);
//   * edge jitter: depth edges are valid pixels with a 4-neighbour that is a hole or differs by
//     more than 0.05 m + 5% of the depth; the mean distance (pixels, each clipped at
//     kMaxEdgeJitterPx) from every edge pixel of a frame to the nearest edge pixel of the
//     previous frame, both ways; on the foreground for raw and filtered depth (people move, so
//     compare the two at equal motion), and on the static background for the raw depth (where
//     the true edges stand still, so any jitter is the sensor's).
// Units: shares in [0, 1], millimetres, pixels. Nothing to measure gives NaN (JSON null).
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <vector>

namespace holo::eval {

inline constexpr float kMaxEdgeJitterPx = 10.0f;
inline constexpr std::array<float, 3> kBackgroundNoiseDepths = {1.0f, 2.0f, 4.0f};

struct DepthStabilityConfig {
  int min_background_samples = 5;
};

struct EdgeAndFlicker {
  double hole_flicker = 0;    // NaN without pixel pairs
  long long pixel_pairs = 0;  // pixel pairs the flicker counts
  double edge_jitter_px = 0;  // NaN without edge pixels
  long long edge_pixels = 0;
};

struct DepthStabilityFigures {
  int frame_pairs = 0;
  EdgeAndFlicker raw;              // the sensor's depth on the foreground
  EdgeAndFlicker filtered;         // the filter's output on the foreground
  EdgeAndFlicker background;       // the sensor's depth on the static background
  double background_noise_mm = 0;  // median per-pixel standard deviation; NaN without pixels
  std::array<double, kBackgroundNoiseDepths.size()> background_noise_mm_at{};
  long long background_noise_pixels = 0;
};

// Accumulates one camera's frames.
class DepthStabilityMeter {
 public:
  explicit DepthStabilityMeter(DepthStabilityConfig config = {});

  // raw, filtered: CV_32FC1 metres, 0 = hole; mask: CV_8UC1, non-zero = foreground. All the same
  // size as the first frame's (holo::Error otherwise).
  void addFrame(const cv::Mat& raw, const cv::Mat& mask, const cv::Mat& filtered);

  DepthStabilityFigures figures() const;
  // Several cameras pooled (pairs, edge pixels and background pixels counted together).
  static DepthStabilityFigures combined(const std::vector<DepthStabilityMeter>& meters);

  // For pictures: per pixel, how often the raw / filtered depth switched between valid and hole
  // on the foreground (CV_32SC1), and the background's temporal standard deviation (CV_32FC1 mm,
  // 0 where too few samples).
  const cv::Mat& rawFlickerCount() const { return raw_switches_; }
  const cv::Mat& filteredFlickerCount() const { return filtered_switches_; }
  cv::Mat backgroundNoiseMm() const;

 private:
  struct Sums {
    long long switches = 0, pairs = 0, edge_pixels = 0;
    double edge_distance = 0;
  };
  void accumulate(Sums& sums, const cv::Mat& previous, const cv::Mat& current, const cv::Mat& region,
                  cv::Mat* switch_count);
  // The background's mean depth and standard deviation at a pixel; false with too few samples.
  bool backgroundPixel(int x, int y, float& mean_m, float& std_mm) const;

  DepthStabilityConfig config_;
  cv::Mat previous_raw_, previous_mask_, previous_filtered_;
  cv::Mat raw_switches_, filtered_switches_;
  cv::Mat background_sum_, background_sum_sq_, background_count_;  // CV_64FC1, CV_64FC1, CV_32SC1
  Sums raw_, filtered_, background_;
  int frame_pairs_ = 0;
};

}  // namespace holo::eval
