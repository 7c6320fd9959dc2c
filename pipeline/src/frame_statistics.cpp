#include "frame_statistics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <ctime>
#include <functional>
#include <initializer_list>
#include <optional>
#include <utility>

namespace holo::pipeline {
namespace {

double passMs(const std::vector<reflect::PassTiming>& timings, std::initializer_list<reflect::Pass> passes) {
  double sum = 0;
  for (const reflect::PassTiming& t : timings)
    if (std::find(passes.begin(), passes.end(), t.pass) != passes.end()) sum += t.ms;
  return sum;
}

// NaN or infinite: every exponent bit set (a bit test, which the compiler vectorises, where
// std::isfinite on three channels branches per pixel).
inline std::uint32_t nonFiniteBit(float value) {
  return (std::bit_cast<std::uint32_t>(value) & 0x7f800000u) == 0x7f800000u ? 1u : 0u;
}

std::int64_t countNonFiniteRow(const float* bgr, int pixels) {
  std::int64_t count = 0;
  for (int x = 0; x < pixels; ++x)
    count += nonFiniteBit(bgr[3 * x]) | nonFiniteBit(bgr[3 * x + 1]) | nonFiniteBit(bgr[3 * x + 2]);
  return count;
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
  // Every view's rows in one parallel loop: four short loops, one per view, would each wake the
  // workers and leave most of the rows to the loop's thread.
  std::vector<std::pair<const cv::Mat*, int>> rows;
  for (const reflect::ViewImages& view : result.views)
    for (int y = 0; y < view.hdr.rows; ++y) rows.emplace_back(&view.hdr, y);
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, rows.size()), std::int64_t(0),
      [&](const tbb::blocked_range<std::size_t>& range, std::int64_t count) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const auto [hdr, y] = rows[i];
          count += countNonFiniteRow(hdr->ptr<float>(y), hdr->cols);
        }
        return count;
      },
      std::plus<>());
}

void addViewCounters(const reflect::FrameResult& result, FrameReport& report) {
  report.plan = result.plan.describe();
  for (const reflect::ViewImages& view : result.views) {
    report.static_reused_views += view.static_reused ? 1 : 0;
    report.static_deferred_views += view.static_deferred ? 1 : 0;
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
