// The live frame loop (docs/architecture.md, "One frame of the live pipeline"): the cameras -> foreground
// point cloud -> reflections per face view -> composition -> the quad view, on an Installation
// (installation.hpp): the simulated museum or the cameras, calibration, relic and panorama of a
// configuration file.
//
// Start-up: the foreground pipeline learns the background from the installation's background
// frames and then from the first `background_frames` frames of every camera (not rendered).
//
// Acquisition overlaps processing in both modes:
//  * live: one capture thread per camera publishes into a latest-frame mailbox; the loop takes
//    the newest frame of each camera and never waits for one. A camera silent for longer than
//    stale_camera_s is dropped from the foreground (the others go on; with none, IBL only).
//  * deterministic (headless runs, tests, benchmarks): every camera's next frame is grabbed in
//    turn on a worker while the current one is processed, so the same scene or recording always
//    gives the same images. A camera that gives no frame within its silence timeout is missing
//    for that frame; a recording that ended stays missing.
//
// Units: seconds for times, milliseconds in StageTimes, metres in the world (pyramid) frame.
// Threads: construct and step() on one thread (a window presenter needs the main thread).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/capture/latest_frame_mailbox.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "holo/display/eye_tracker.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::pipeline {

inline constexpr std::size_t kPassCount = static_cast<std::size_t>(reflect::Pass::ToneMap) + 1;

// The tracer as the live loop runs it: one sample per pixel plus four at silhouette and crease
// pixels (instead of four everywhere), each view's static passes reused while its eye moves
// less than 1 cm, and no interreflection bounce. Their (time, error) points:
// docs/frame_loop.md.
reflect::TracerSettings liveTracerSettings();
// The tracer's samples for an anti-aliasing mode (hit_points.hpp).
void setAntiAliasing(reflect::TracerSettings& tracer, reflect::AntiAliasing mode);

struct FrameLoopOptions {
  std::string scene = "museum";  // built-in name or YAML file (sim::loadScene)
  std::string relic;             // replaces the scene's relic (built-in name or glTF file); empty: keep
  // A configuration file with `capture:` and `exhibit:` sections (installation.hpp): its cameras,
  // calibration, relic and panorama instead of the simulated scene. Empty: `scene`.
  std::string config;
  bool live = false;         // capture threads at the cameras' rate; else deterministic
  int view_size = 320;       // pixels, square face views
  int panorama_width = 512;  // of the simulated hall panorama the IBL is built from (scene)
  // The reflections read the panorama at infinity from its capture point instead of through the
  // installation's proxy (Installation::panorama_proxy): as before the proxy existed.
  bool panorama_at_infinity = false;
  double stale_camera_s = 0.5;  // live: a camera silent this long leaves the foreground
  bool track_eyes = true;       // eyes follow visitors' heads; else default standing eyes
  // Deterministic mode: grab (simulate) the first N frames of every camera before the first step
  // and replay them from memory (later frames are grabbed while the previous one is processed).
  // For benchmarks: real cameras deliver their frames, while simulating four of them costs as
  // much CPU as a frame and would compete with it on 2 cores. About 6.5 MB per frame.
  int preload_frames = 0;
  // The next frame's acquisition and foreground point cloud run on a worker thread while this
  // frame's reflections are rendered and presented. Results are the same either way (the
  // foreground and the rendering each keep their own order); only the time differs.
  bool overlap = true;
  reflect::TracerSettings tracer = liveTracerSettings();
  display::EyeTrackerSettings eyes;
};

// The paper's Table 3 stages of one frame, milliseconds.
struct StageTimes {
  double acquisition = 0;  // waiting for camera frames (their grabbing overlaps processing)
  double foreground = 0;   // masks, flow, temporal filter, back-projection, voxel grid
  double dynamic = 0;      // Kawase pyramids and voxel walk (reflected and transmitted rays)
  double statics = 0;      // hit points, prefiltered IBL, refraction through the relic, clearcoat
  double composition = 0;  // composition, tone mapping
  double display = 0;      // eye tracking, quad layout, presentation
  double total = 0;        // the frame's wall time on the loop's thread (the frame period)
  // Overlap: how long the frame waited for its foreground, computed on the worker while the
  // previous frame was rendered (about 0 when it was ready); without: acquisition + foreground.
  double pipeline_wait = 0;
  // The appliance's own work, one stage after another: foreground, reflections, composition,
  // display (not acquisition, which waits for the cameras).
  double applianceStages() const { return foreground + dynamic + statics + composition + display; }
};

struct FrameReport {
  std::int64_t index = 0;
  StageTimes times;
  std::size_t foreground_points = 0;
  int cameras_live = 0;  // cameras whose frame reached the foreground stage
  // Newest - oldest arrival time (host clock, ms) of the camera frames this frame was made of;
  // -1 with fewer than 2 of them.
  double camera_skew_ms = -1;
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
  int static_reused_views = 0;     // views whose hit points and static shading came from the cache
  std::size_t refined_pixels = 0;  // pixels with 4 sub-samples (edge anti-aliasing), all views
  std::size_t relic_pixels = 0;    // pixels with some relic coverage, all views
  // Embree rays through transmissive relic materials, transmitted exit rays walked, and samples
  // whose transmitted light is a mean of paths (supersampled), all views (0 for an opaque relic:
  // the plan runs no refraction pass).
  std::uint64_t refraction_rays = 0, refracted_walks = 0, supersampled_samples = 0;
  // Milliseconds per reflect::Pass (index = the enum's value), summed over the views; plus the
  // camera images' conversion to linear colour for the pyramids (part of `dynamic`).
  std::array<double, kPassCount> pass_ms{};
  double camera_images_ms = 0;
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

class FrameLoop {
 public:
  // Builds the installation (options.config, else options.scene), opens its cameras, learns the
  // background, builds the IBL and the renderers. Throws InputError for a bad scene, configuration
  // or settings. `presenter` may be null (benchmarks: render without showing).
  FrameLoop(FrameLoopOptions options, std::unique_ptr<display::QuadViewPresenter> presenter);
  // The same on an installation built by the caller (options.scene and .config are not used).
  FrameLoop(FrameLoopOptions options, Installation installation,
            std::unique_ptr<display::QuadViewPresenter> presenter);
  ~FrameLoop();
  FrameLoop(const FrameLoop&) = delete;
  FrameLoop& operator=(const FrameLoop&) = delete;

  // Renders and presents one frame (and, with overlap, starts the next frame's foreground).
  FrameReport step();
  // Waits until the worker has finished the next frame's foreground (benchmarks: nothing runs
  // beside what they measure next).
  void waitForWorker() const;
  // The last frame again, from the eyes of that frame, with other tracer settings (and the
  // loop's exposure): the reference a quality knob's error is measured against (bench frame).
  reflect::FrameResult renderReference(reflect::TracerSettings settings);
  // Lower quality for the kiosk's degradation: view size and whether the foreground runs.
  void setQuality(int view_size, bool foreground_enabled);
  // Closes the presenter's outputs (the MP4 is renamed into place).
  void finish();

  const std::string& installationName() const { return installation_name_; }
  double cameraFps() const { return fps_; }
  const std::vector<CameraModel>& cameras() const { return cameras_; }
  std::vector<CameraModel> faceViews() const;  // the four views of the last frame
  const reflect::FrameResult& lastResult() const { return last_result_; }
  std::vector<capture::CameraHealth> cameraHealth() const;
  CameraFrameCounts cameraFrameCounts() const;
  display::QuadViewPresenter* presenter() { return presenter_.get(); }
  const reflect::RenderScene& renderScene() const { return *render_scene_; }
  const reflect::PrefilteredIbl& ibl() const { return ibl_; }

 private:
  // One frame of every camera (empty where a camera gave none) and whether all streams ended.
  struct CameraFrames {
    std::vector<RgbdFrame> frames;
    bool ended = false;
  };
  CameraFrames acquire(double& wait_ms);
  CameraFrames grabDeterministic();  // the next frame of every source, in parallel
  RgbdFrame grabFrom(std::size_t camera);
  std::vector<RgbdFrame> waitLive();  // live: a fresh frame of every camera (bounded wait)
  void learnBackground(const Installation& installation);
  // Acquisition and the foreground stage of one frame (on the loop's worker when overlapped).
  struct ForegroundFrame {
    CameraFrames acquired;
    depthfilter::ForegroundCloud cloud;
    std::vector<cv::Mat> masks;  // per camera, copied from the pipeline; empty: no image
    int cameras_live = 0;
    double camera_skew_ms = -1;  // FrameReport::camera_skew_ms
    double acquisition_ms = 0, foreground_ms = 0;
  };
  ForegroundFrame runForeground();
  // Frames the foreground cannot use (no depth, a size other than the calibrated camera's) become
  // missing ones, with a warning per camera and problem: a camera never stops the loop.
  void rejectUnusable(std::vector<RgbdFrame>& frames);
  // The calibration's fitted depth scale (Installation::depth_correction), then two-device
  // cameras' depth reprojected into their colour image (Installation::depth_to_colour).
  void correctDepth(std::vector<RgbdFrame>& frames) const;
  std::vector<reflect::ForegroundCameraImage> cameraImages(const std::vector<RgbdFrame>& frames,
                                                           const std::vector<cv::Mat>& masks);

  FrameLoopOptions options_;
  std::string installation_name_;
  bool simulated_cameras_ = false;
  double fps_ = 30.0;
  std::vector<CameraModel> cameras_;
  // Deterministic mode: the sources, grabbed by one task at a time (the prefetch), and which of
  // them reported the end of their stream.
  std::vector<std::unique_ptr<capture::CameraSource>> sources_;
  std::vector<capture::CaptureOptions> capture_options_;
  std::vector<std::uint8_t> source_ended_;
  std::deque<CameraFrames> preloaded_;                                   // deterministic
  std::future<CameraFrames> next_frames_;                                // deterministic prefetch
  std::vector<std::unique_ptr<capture::LatestFrameMailbox>> mailboxes_;  // live mode
  std::vector<std::unique_ptr<capture::CaptureThread>> threads_;         // live mode
  std::vector<RgbdFrame> latest_;                                        // live: per camera
  std::future<ForegroundFrame> next_foreground_;  // overlap: the next frame's, in flight
  std::vector<std::string> rejected_;             // per camera: the last unusable frame's problem
  std::atomic<std::int64_t> rejected_frames_{0};  // camera frames rejectUnusable dropped (worker)
  std::vector<cv::Mat> linear_colour_;            // per camera, reused: the pyramids copy what they keep
  std::vector<reflect::ForegroundCameraImage> last_images_;  // the last frame's, for renderReference
  depthfilter::ForegroundPipeline foreground_;
  depthfilter::ForegroundCloud cloud_;
  float camera_exposure_ = 1.0f;         // the cameras': radiance = srgbToLinear(colour) / exposure
  std::vector<vec3> colour_gains_;       // per camera, linear RGB (Installation::colour_gains)
  std::vector<float> depth_correction_;  // per camera (Installation::depth_correction)
  std::vector<std::optional<capture::DepthToColour>> depth_to_colour_;  // per camera
  reflect::Environment environment_;
  reflect::PrefilteredIbl ibl_;
  std::unique_ptr<reflect::RenderScene> render_scene_;
  std::unique_ptr<reflect::FrameRenderer> renderer_;
  display::EyeTracker eye_tracker_;
  std::unique_ptr<display::QuadViewPresenter> presenter_;
  std::array<vec3, 4> eyes_{};
  std::optional<float> exposure_;  // fixed after the first frame so the image does not pump
  reflect::FrameResult last_result_;
  std::int64_t index_ = 0;
  std::int64_t dropped_before_ = 0;  // mailbox drops counted up to the previous step
};

// Median of each stage over the reports, and frames per second from the median total.
StageTimes medianTimes(const std::vector<FrameReport>& reports);
// Median milliseconds per reflect::Pass over the reports, by pass name, plus "CameraImages".
std::vector<std::pair<std::string, double>> medianPasses(const std::vector<FrameReport>& reports);
// The Table 3 style text table (with the run's non-finite pixels and dropped camera frames) and
// its JSON form. With simulated cameras, their rendering (the acquisition wait) is shown apart
// from the appliance's own stages, whose sum gives the pipeline's own frame rate without overlap
// (a lower bound: the stages still share the cores with the simulation); `holopyramid bench
// frame` measures it with the cameras simulated before timing.
std::string formatTimingTable(const StageTimes& median, const std::vector<FrameReport>& reports,
                              const CameraFrameCounts& cameras);
std::string timingJson(const StageTimes& median, const std::vector<FrameReport>& reports,
                       const CameraFrameCounts& cameras);

}  // namespace holo::pipeline
