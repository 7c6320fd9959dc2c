// What the live frame loop (frame_loop.hpp) reports: per frame, the time of each of the paper's
// Table 3 stages and of each tracer pass and the frame's counters; over the run, the camera
// frames produced, consumed and dropped. The loop only collects these numbers; the medians, the
// timing table and its JSON are eval's (eval/frame_timing_report.hpp).
//
// Units: milliseconds for times, pixels and rays for counters.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/rgbd_frame.hpp"
#include "holo/reflect/effect_plan.hpp"

namespace holo::pipeline {

inline constexpr std::size_t kPassCount = static_cast<std::size_t>(reflect::Pass::ToneMap) + 1;

// The paper's Table 3 stages of one frame, milliseconds.
struct StageTimes {
  double acquisition = 0;  // waiting for camera frames (their grabbing overlaps processing)
  double foreground = 0;   // masks, flow, temporal filter, back-projection, voxel grid
  // Kawase pyramids, the rough foreground map, the visitors' light and the voxel walk (reflected
  // and transmitted rays)
  double dynamic = 0;
  // hit points, self-occlusion, prefiltered IBL and its filtered lobe, refraction through the
  // relic, clearcoat, progressive refinement
  double statics = 0;
  double composition = 0;  // composition, tone mapping
  double display = 0;      // eye tracking, quad layout, presentation
  double total = 0;        // the frame's wall time on the loop's thread (the frame period)
  // Overlap: how long the frame waited for its foreground, computed on the worker during the
  // previous frame (deterministic: its rendering and presentation; live: its presentation only;
  // about 0 when it was ready); without: acquisition + foreground.
  double pipeline_wait = 0;
  // The appliance's own work, one stage after another: foreground, reflections, composition,
  // display (not acquisition, which waits for the cameras).
  double applianceStages() const { return foreground + dynamic + statics + composition + display; }
};

// Where a frame's arrival-to-present latency went, ms; the parts add up to
// FrameReport::arrivalToPresentMs().
struct LatencyParts {
  double in_mailbox = 0;  // the oldest camera frame shown, from its arrival until the foreground step took it
  double foreground = 0;  // the foreground step (depth filter, masks, point cloud)
  double waiting_for_loop = 0;  // its result, until the loop's thread started rendering with it
  double rendering = 0;         // eye tracking, the reflections of the four views, composition
  double presenting = 0;        // handing the views to the presenter
};

// CPU time spent during one stage of a frame, ms: by the loop's thread (the one running the
// stage) and by the whole process (every thread). With the foreground not overlapped and no other
// work in the process, the process's is the stage's own work; the loop thread's share of it tells
// the stage's serial part from its parallel part (bench scaling).
struct StageCpu {
  double loop_thread_ms = 0, process_ms = 0;
};

struct FrameReport {
  std::int64_t index = 0;
  StageTimes times;
  std::size_t foreground_points = 0;
  int cameras_live = 0;  // cameras whose frame reached the foreground stage
  // Newest - oldest arrival time (host clock, ms) of the camera frames this frame was made of;
  // -1 with fewer than 2 of them.
  double camera_skew_ms = -1;
  // When each camera frame this frame was made of reached the host (RgbdFrame::host_time), per
  // camera in the installation's order; nullopt where a camera gave none.
  std::vector<std::optional<Clock::time_point>> camera_arrivals;
  // Per camera, the source's sequence number (RgbdFrame::sequence) of the frame used; nullopt
  // where a camera gave none.
  std::vector<std::optional<std::uint64_t>> camera_sequences;
  // When the frame's foreground step took its camera frames from the cameras and when it had the
  // point cloud; when the loop's thread started rendering with that foreground (eye tracking on)
  // and when the four views were ready.
  Clock::time_point acquired_at, foreground_done_at, rendering_started_at, rendering_done_at;
  // When the frame was handed to the presenter (without one: when it was ready to be).
  Clock::time_point presented_at;
  // presented_at - the oldest camera arrival, ms: how long the oldest visitor picture this frame
  // shows had waited when it reached the screen (the presenter's own scan-out not included);
  // -1 without a camera frame. Meaningful live (deterministic runs stamp frames when grabbed).
  double arrivalToPresentMs() const {
    const std::optional<Clock::time_point> oldest = oldestArrival();
    return oldest ? std::chrono::duration<double, std::milli>(presented_at - *oldest).count() : -1.0;
  }
  // arrivalToPresentMs() split at the stamps above; all zero without a camera frame.
  LatencyParts latencyParts() const {
    const std::optional<Clock::time_point> oldest = oldestArrival();
    if (!oldest) return {};
    auto ms = [](Clock::time_point from, Clock::time_point to) {
      return std::chrono::duration<double, std::milli>(to - from).count();
    };
    return {ms(*oldest, acquired_at), ms(acquired_at, foreground_done_at),
            ms(foreground_done_at, rendering_started_at), ms(rendering_started_at, rendering_done_at),
            ms(rendering_done_at, presented_at)};
  }
  std::optional<Clock::time_point> oldestArrival() const {
    std::optional<Clock::time_point> oldest;
    for (const auto& arrival : camera_arrivals)
      if (arrival && (!oldest || *arrival < *oldest)) oldest = arrival;
    return oldest;
  }
  std::string plan;  // the effect plan of face 0 ("HitPoints,... (reason)")
  std::array<bool, 4> eyes_tracked{};
  bool presented = false;
  // HDR pixels of the four views with a NaN or infinite channel (the composition guarantees 0;
  // counted, not assumed, so a run proves it).
  std::int64_t non_finite_pixels = 0;
  // Camera frames overwritten in the mailboxes since the previous step, all cameras: produced by
  // a capture thread, never consumed by the loop. Live mode only; deterministic mode renders
  // exactly the frames it consumes, so 0 by construction.
  std::int64_t dropped_frames = 0;
  // Every camera's stream has ended (recordings played to their end): nothing more will come,
  // and this report is not a frame (nothing was rendered or presented).
  bool cameras_ended = false;
  int static_reused_views = 0;  // views whose hit points and static shading came from the cache
  // Of those, the views due a trace that the frame's budget left to a later frame.
  int static_deferred_views = 0;
  std::size_t refined_pixels = 0;  // pixels with 4 sub-samples (edge anti-aliasing), all views
  std::size_t relic_pixels = 0;    // pixels with some relic coverage, all views
  // Embree rays through transmissive relic materials, transmitted exit rays walked, and samples
  // whose transmitted light is a mean of paths (supersampled), all views (0 for an opaque relic:
  // the plan runs no refraction pass).
  std::uint64_t refraction_rays = 0, refracted_walks = 0, supersampled_samples = 0;
  // Relic samples shaded, those that cast an interreflection ray and the rays, all views (0 for
  // views whose static shading was reused).
  std::uint64_t shaded_samples = 0, interreflected_samples = 0, interreflection_rays = 0;
  // Milliseconds per reflect::Pass (index = the enum's value), summed over the views; plus the
  // camera images' conversion to linear colour for the pyramids (part of `dynamic`).
  std::array<double, kPassCount> pass_ms{};
  double camera_images_ms = 0;
  // The CPU of the frame's foreground step (acquired_at to foreground_done_at, on whichever thread
  // ran it), its rendering (rendering_started_at to rendering_done_at) and its presentation.
  StageCpu foreground_cpu, rendering_cpu, presenting_cpu;
};

// Camera frames over the whole run, all cameras. Live: from the mailboxes' counters, and
// `unconsumed` = produced - consumed (the drops plus frames still waiting in a mailbox).
// Deterministic: produced = consumed = frames x cameras.
struct CameraFrameCounts {
  bool live = false;
  // Installation::simulated_cameras, and simulated during the run (not preloaded): their rendering
  // is in the acquisition wait.
  bool simulated = false;
  std::int64_t produced = 0;
  std::int64_t consumed = 0;
  std::int64_t dropped = 0;
  std::int64_t unconsumed = 0;
  std::int64_t rejected = 0;  // taken but unusable (no depth, wrong size): treated as missing
};

}  // namespace holo::pipeline
