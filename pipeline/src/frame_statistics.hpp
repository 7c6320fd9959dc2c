// How the frame loop fills its FrameReport (frame_report.hpp) from what a frame is made of: the
// camera frames that reached the foreground stage, and the renderer's pass timings and view
// counters, summed into the Table 3 stages.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/rgbd_frame.hpp"
#include "holo/pipeline/frame_report.hpp"
#include "holo/reflect/frame_renderer.hpp"

namespace holo::pipeline {

// The camera frames with a colour image (they reach the foreground stage) and the spread of their
// arrival times (FrameReport::cameras_live, camera_skew_ms).
struct CameraArrival {
  int live = 0;
  double skew_ms = -1;  // -1 with fewer than 2 live frames
};
CameraArrival cameraArrival(const std::vector<RgbdFrame>& frames);

// Adds the frame's pass timings to `report`: each pass into pass_ms (all views), and the passes
// into their stages: the voxel grid into foreground; pyramids and the walks into dynamic; hit
// points, static reflections, refraction and clearcoat into statics; composition and tone mapping
// into composition.
void addPassTimes(const reflect::FrameResult& result, FrameReport& report);

// Measures the CPU a stage takes (StageCpu) from construction to stop(), on the constructing
// thread and in the whole process.
class StageCpuClock {
 public:
  StageCpuClock();
  StageCpu stop() const;

 private:
  double thread_start_ms_, process_start_ms_;
};

// HDR pixels with a NaN or infinite channel over the frame's views.
std::int64_t nonFinitePixels(const reflect::FrameResult& result);

// The frame's effect plan and the views' counters (static reuse, refined and relic pixels,
// refraction rays, refracted walks, supersampled samples), added to `report`.
void addViewCounters(const reflect::FrameResult& result, FrameReport& report);

}  // namespace holo::pipeline
