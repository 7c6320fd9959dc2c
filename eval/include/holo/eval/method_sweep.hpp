// What accuracy costs in time (`holopyramid eval reflections`): every reflection method
// (methods.hpp) at a few quality settings on one view, each scored against the path-traced truth
// (ground_truth_cache.hpp) over the whole view (mse) and over the dynamic-foreground reflection
// region (fg_mse; paper Sec. 4.1.2: the linear truths with and without the visitors differ by an
// RGB distance >= 0.2). Errors are on linear HDR images; times in milliseconds per view.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"

namespace holo::eval {

struct MethodPoint {
  std::string method, knob;
  MethodSettings settings;
  double ms = 0, mse = 0, fg_mse = 0;
  cv::Mat image;  // linear HDR CV_32FC3 BGR
};

// The (method, knob) points: the first of each method is its default; the rest trace the
// time/error curve. `full` adds the slow, high-quality settings; ground-truth points at gt_spp
// or more are left out.
std::vector<MethodPoint> plannedMethodPoints(bool full, int gt_spp);

struct MethodSweep {
  cv::Mat truth;   // the ground truth with the visitors, linear HDR
  cv::Mat region;  // CV_8UC1, 255 in the foreground region (none without visitors)
  int region_pixels = 0;
  std::vector<MethodPoint> points;  // plannedMethodPoints, rendered and scored
};

// Ground truths come from (or go to) the folder `cache`.
MethodSweep sweepMethods(const ReflectionScene& scene, const CameraModel& camera, bool full, int gt_spp,
                         const std::string& cache);

}  // namespace holo::eval
