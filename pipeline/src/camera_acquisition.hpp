// The frame loop's cameras (frame_loop.hpp): one frame of every camera per call, fit for the
// foreground pipeline, in one of two modes.
//  * live: one capture thread per camera publishes into a latest-frame mailbox; next() takes the
//    newest frame of each camera, waiting only for a camera whose next frame is predicted within
//    `fresh_frame_wait` (arrival_prediction.hpp; 0: never waits). A camera silent for longer than
//    stale_camera_s is missing (the others go on).
//  * deterministic: every camera's next frame is grabbed in turn on a worker (the prefetch) while
//    the caller processes the current one, so the same scene or recording always gives the same
//    frames. A camera that gives no frame within its silence timeout is missing for that frame; a
//    recording that ended stays missing. preload() grabs frames ahead into memory.
//
// Every frame handed out has its depth corrected (the calibration's fitted depth scale, then a
// two-device camera's depth reprojected into its colour image) and a frame the foreground cannot
// use (no depth, a size other than the calibrated camera's) replaced by a missing (empty) one,
// with a warning per camera and problem: a camera never stops the loop.
//
// Units: milliseconds for waits, seconds for staleness. Threads: next(), backgroundFrame() and
// preload() one call at a time, on any one thread at a time (the loop's worker); cameraHealth()
// and counts() from any thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrival_prediction.hpp"
#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/capture/depth_to_colour.hpp"
#include "holo/capture/latest_frame_mailbox.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/pipeline/frame_report.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::pipeline {

class CameraAcquisition {
 public:
  // One frame of every camera, in the installation's order (empty where a camera gave none).
  struct Frames {
    std::vector<RgbdFrame> frames;
    bool ended = false;  // every stream has ended: nothing more will come
    double wait_ms = 0;  // how long next() waited for them (the grabbing overlaps processing)
    // When they were taken: live, the last look into the mailboxes (every frame that had arrived
    // by then is among them, after any wait for a frame about to arrive); deterministic, when
    // next() was called.
    Clock::time_point taken_at;
  };

  // Takes the installation's sources (installation.sources is left empty), cameras, capture
  // settings and depth corrections, and starts the capture threads (live) or opens and starts the
  // sources (deterministic). The installation has one source and capture setting per camera.
  CameraAcquisition(Installation& installation, bool live, double stale_camera_s,
                    Clock::duration fresh_frame_wait = Clock::duration::zero());
  // Stops the capture threads, waits for the prefetch, then stops the sources.
  ~CameraAcquisition();
  CameraAcquisition(const CameraAcquisition&) = delete;
  CameraAcquisition& operator=(const CameraAcquisition&) = delete;

  // The next frame of every camera: deterministic, the preloaded frames first, then the prefetch
  // (started here for the frame after); live, each camera's newest frame, or none when stale.
  Frames next();
  // A frame of every camera to learn the background from: live, waits for a fresh frame of each
  // camera (bounded by its silence timeout); deterministic, grabs one now.
  std::vector<RgbdFrame> backgroundFrame();
  // Deterministic mode: grabs the next `frames` frames of every camera now; next() replays them
  // first. About 6.5 MB per frame of four simulated cameras. Live mode: nothing (the cameras
  // deliver at their own rate).
  void preload(int frames);
  // The depth correction every frame gets (see above), on frames from elsewhere (the
  // calibration's background, measured by the same cameras). Into new buffers: a frame's depth
  // may be shared.
  void correctDepth(std::vector<RgbdFrame>& frames) const;

  // Per camera: live, the capture threads' health; deterministic, always connected, with
  // `frames_rendered` frames completed.
  std::vector<capture::CameraHealth> cameraHealth(std::int64_t frames_rendered) const;
  // The run's camera frames (CameraFrameCounts; `simulated` is left false for the caller):
  // deterministic, produced = consumed = frames_rendered x cameras.
  CameraFrameCounts counts(std::int64_t frames_rendered) const;

 private:
  struct Grabbed {
    std::vector<RgbdFrame> frames;
    bool ended = false;
    Clock::time_point taken_at;  // live: see Frames::taken_at
  };
  Grabbed grabDeterministic();  // the next frame of every source, in parallel
  RgbdFrame grabFrom(std::size_t camera);
  Grabbed takeLive();                 // each mailbox's newest frame, or the last one while fresh
  void takeNewestLive();              // into latest_, each taken frame's arrival observed
  void waitForFramesAboutToArrive();  // the cameras whose next frame is due within fresh_frame_wait_
  std::vector<RgbdFrame> waitLive();  // a fresh frame of every camera (bounded wait)
  void rejectUnusable(std::vector<RgbdFrame>& frames);

  bool live_;
  double stale_camera_s_;
  Clock::duration fresh_frame_wait_;
  std::vector<CameraModel> cameras_;
  std::vector<capture::CaptureOptions> capture_options_;
  std::vector<float> depth_correction_;                                 // per camera
  std::vector<std::optional<capture::DepthToColour>> depth_to_colour_;  // per camera
  // Deterministic: the sources, grabbed by one task at a time (the prefetch), and which of them
  // reported the end of their stream.
  std::vector<std::unique_ptr<capture::CameraSource>> sources_;
  std::vector<std::uint8_t> source_ended_;
  std::deque<Grabbed> preloaded_;
  std::future<Grabbed> next_frames_;  // the prefetch
  // Live: per camera, the mailbox its capture thread publishes into and the newest frame taken.
  std::vector<std::unique_ptr<capture::LatestFrameMailbox>> mailboxes_;
  std::vector<std::unique_ptr<capture::CaptureThread>> threads_;
  std::vector<RgbdFrame> latest_;
  std::vector<ArrivalPredictor> arrivals_;        // per camera, from the frames taken
  std::vector<std::string> rejected_;             // per camera: the last unusable frame's problem
  std::atomic<std::int64_t> rejected_frames_{0};  // frames rejectUnusable replaced, all cameras
};

}  // namespace holo::pipeline
