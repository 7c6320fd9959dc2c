#include "frame_statistics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <initializer_list>
#include <optional>

namespace holo::pipeline {
namespace {

double passMs(const std::vector<reflect::PassTiming>& timings, std::initializer_list<reflect::Pass> passes) {
  double sum = 0;
  for (const reflect::PassTiming& t : timings)
    if (std::find(passes.begin(), passes.end(), t.pass) != passes.end()) sum += t.ms;
  return sum;
}

std::int64_t countNonFinite(const cv::Mat& hdr) {
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, hdr.rows), std::int64_t(0),
      [&](const tbb::blocked_range<int>& rows, std::int64_t count) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          const float* row = hdr.ptr<float>(y);
          for (int x = 0; x < hdr.cols; ++x) {
            const float* p = row + 3 * x;
            count += (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) ? 0 : 1;
          }
        }
        return count;
      },
      std::plus<>());
}

double cpuClockMs(clockid_t clock) {
  timespec t{};
  ::clock_gettime(clock, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

}  // namespace

StageCpuClock::StageCpuClock()
    : thread_start_ms_(cpuClockMs(CLOCK_THREAD_CPUTIME_ID)),
      process_start_ms_(cpuClockMs(CLOCK_PROCESS_CPUTIME_ID)) {}

StageCpu StageCpuClock::stop() const {
  return {cpuClockMs(CLOCK_THREAD_CPUTIME_ID) - thread_start_ms_,
          cpuClockMs(CLOCK_PROCESS_CPUTIME_ID) - process_start_ms_};
}

CameraArrival cameraArrival(const std::vector<RgbdFrame>& frames) {
  CameraArrival out;
  std::optional<Clock::time_point> oldest, newest;
  for (const RgbdFrame& f : frames) {
    if (f.colour.empty()) continue;
    ++out.live;
    if (!oldest || f.host_time < *oldest) oldest = f.host_time;
    if (!newest || f.host_time > *newest) newest = f.host_time;
  }
  if (out.live >= 2) out.skew_ms = std::chrono::duration<double, std::milli>(*newest - *oldest).count();
  return out;
}

void addPassTimes(const reflect::FrameResult& result, FrameReport& report) {
  for (const reflect::PassTiming& t : result.frame_timings) report.pass_ms[std::size_t(t.pass)] += t.ms;
  for (const reflect::ViewImages& view : result.views)
    for (const reflect::PassTiming& t : view.timings) report.pass_ms[std::size_t(t.pass)] += t.ms;
  report.times.foreground += passMs(result.frame_timings, {reflect::Pass::VoxelGrid});
  report.times.dynamic +=
      passMs(result.frame_timings,
             {reflect::Pass::Pyramids, reflect::Pass::RoughForegroundMap, reflect::Pass::VisitorLight});
  report.times.statics += passMs(result.frame_timings, {reflect::Pass::SelfOcclusion});
  for (const reflect::ViewImages& view : result.views) {
    report.times.dynamic +=
        passMs(view.timings, {reflect::Pass::ForegroundWalk, reflect::Pass::RefractedForeground});
    report.times.statics +=
        passMs(view.timings,
               {reflect::Pass::HitPoints, reflect::Pass::StaticReflections, reflect::Pass::AxisAlignedFilter,
                reflect::Pass::Refraction, reflect::Pass::Clearcoat, reflect::Pass::ProgressiveRefinement});
    report.times.composition += passMs(view.timings, {reflect::Pass::Composition, reflect::Pass::ToneMap});
  }
}

std::int64_t nonFinitePixels(const reflect::FrameResult& result) {
  std::int64_t count = 0;
  for (const reflect::ViewImages& view : result.views) count += countNonFinite(view.hdr);
  return count;
}

void addViewCounters(const reflect::FrameResult& result, FrameReport& report) {
  report.plan = result.plan.describe();
  for (const reflect::ViewImages& view : result.views) {
    report.static_reused_views += view.static_reused ? 1 : 0;
    report.refined_pixels += view.refined_pixels;
    report.refraction_rays += view.refraction_rays;
    report.refracted_walks += view.refracted_walks;
    report.supersampled_samples += view.supersampled_samples;
    report.shaded_samples += view.shaded_samples;
    report.interreflected_samples += view.interreflected_samples;
    report.interreflection_rays += view.interreflection_rays;
    if (!view.coverage.empty())
      report.relic_pixels += static_cast<std::size_t>(cv::countNonZero(view.coverage));
  }
}

}  // namespace holo::pipeline
