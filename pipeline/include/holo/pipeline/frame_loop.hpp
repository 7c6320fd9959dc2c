// The live frame loop (docs/architecture.md, "One frame of the live pipeline"): the cameras -> foreground
// point cloud -> reflections per face view -> composition -> the quad view, on an Installation
// (installation.hpp): the simulated museum or the cameras, calibration, relic and panorama of a
// configuration file.
//
// Start-up: the foreground pipeline learns the background from the installation's background
// frames and then from the first `background_frames` frames of every camera (not rendered).
//
// Acquisition overlaps processing in both modes (camera_acquisition.hpp in pipeline/src):
//  * live: one capture thread per camera publishes into a latest-frame mailbox; the foreground
//    step takes the newest frame of each camera once the previous frame is rendered (so no
//    camera frame waits through another frame's rendering), waiting only for a frame predicted
//    within fresh_frame_wait_ms. A camera
//    silent for longer than stale_camera_s is dropped from the foreground (the others go on;
//    with none, IBL only).
//  * deterministic (headless runs, tests, benchmarks): every camera's next frame is grabbed in
//    turn on a worker while the current one is processed, so the same scene or recording always
//    gives the same images. A camera that gives no frame within its silence timeout is missing
//    for that frame; a recording that ended stays missing.
//
// Each step() reports the frame's stage times and counters (frame_report.hpp); the medians,
// the timing table and its JSON are eval's (eval/frame_timing_report.hpp).
//
// The exhibit's playlist (kiosk_frame_source.hpp) changes what the loop shows between frames:
//  * setStage switches in another relic on its hall (a RelicStage: the relic's ray scenes and its
//    hall's prefiltered IBL, built by buildStage off the loop's thread while the current relic
//    shows); the renderer is rebuilt for it, so its effect plan is the new relic's (refraction
//    passes only for a glass relic), and the exposure is chosen again on its first frame.
//  * setTurn turns the relic about the vertical line through its bounds' centre (a turntable).
//    The relic's ray scenes (its BVH) and the IBL are kept: the renderer traces the still relic
//    from eyes, visitors and a hall turned the other way (PrefilteredIbl::setRelicTurn), which
//    gives the turned relic's picture. What a turn does not keep is the per-view cache of hit
//    points and static shading (frame_renderer.hpp): it is reused only while a view's eye, seen
//    from the turning relic, stays within static_reuse_distance, as for a visitor's moving eye;
//    a relic that does not turn reuses it exactly as without a playlist. A turning relic is
//    framed by the cylinder it sweeps, so its size on screen does not breathe.
//  * setCrossfade blends the picture presented with given faces (the outgoing relic's last
//    ones) for a cross-fade.
//
// Units: seconds for times, milliseconds in StageTimes, metres in the world (pyramid) frame,
// radians for turns.
// Threads: construct and step() on one thread (a window presenter needs the main thread).
#pragma once

#include <array>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "holo/capture/camera_source.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "holo/display/eye_tracker.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/pipeline/frame_report.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::pipeline {

class CameraAcquisition;

// The tracer as the live loop runs it: one sample per pixel plus four at silhouette and crease
// pixels (instead of four everywhere), each view's static passes reused while its eye moves
// less than 1 cm and traced again by one view a frame while the others' eyes have moved less
// than 5 cm (eyes that move together do not make one frame several times longer), and the
// interreflection bounce where the relic can see itself (none on a convex relic:
// effect_plan.hpp). Their (time, error) points: docs/frame_loop.md.
reflect::TracerSettings liveTracerSettings();
// The tracer's samples for an anti-aliasing mode (hit_points.hpp).
void setAntiAliasing(reflect::TracerSettings& tracer, reflect::AntiAliasing mode);

inline constexpr int kViewSizeFromScreen = 0;

struct FrameLoopOptions {
  // Which installation to run on (simulated::installationFor builds it; the loop runs on the one
  // it is given). `scene`: built-in name or YAML file of the simulated museum (sim::loadScene).
  std::string scene = "museum";
  std::string relic;  // replaces the scene's relic (built-in name or glTF file); empty: keep
  // A configuration file with `capture:` and `exhibit:` sections (installation.hpp): its cameras,
  // calibration, relic and panorama instead of the simulated scene. Empty: `scene`.
  std::string config;
  bool live = false;  // capture threads at the cameras' rate; else deterministic
  // Pixels, square face views; kViewSizeFromScreen: the presenter's screen and layout decide
  // (display::screenFaceViewPixels: a Full HD cross gives 360), which needs a presenter.
  int view_size = 320;
  int panorama_width = 512;  // of the simulated hall panorama the IBL is built from (scene)
  // The reflections read the panorama at infinity from its capture point instead of through the
  // installation's proxy (Installation::panorama_proxy): no parallax, for comparisons.
  bool panorama_at_infinity = false;
  double stale_camera_s = 0.5;  // live: a camera silent this long leaves the foreground
  // Live: milliseconds the foreground step waits for a camera whose next frame is predicted
  // within them (its frame shown that much newer, the frame that much later; 0: never waits;
  // docs/frame_loop.md, "Waiting for a camera frame about to arrive").
  double fresh_frame_wait_ms = 10.0;
  bool track_eyes = true;  // eyes follow visitors' heads; else default standing eyes
  // Deterministic mode: grab (simulate) the first N frames of every camera before the first step
  // and replay them from memory (later frames are grabbed while the previous one is processed).
  // For benchmarks: real cameras deliver their frames, while simulating four of them costs as
  // much CPU as a frame and would compete with it on 2 cores. About 6.5 MB per frame.
  int preload_frames = 0;
  // The next frame's acquisition and foreground point cloud run on a worker thread beside this
  // frame: deterministic, while its reflections are rendered and presented; live, while it is
  // presented only (camera frames taken before a rendering ends would wait through it, a whole
  // rendering of latency: docs/frame_loop.md, "Latency and stutter"). Results are the same
  // either way (the foreground and the rendering each keep their own order); only the time
  // differs.
  bool overlap = true;
  reflect::TracerSettings tracer = liveTracerSettings();
  display::EyeTrackerSettings eyes;
};

// A relic on its hall, ready to be shown: everything its frames need that takes long to build.
struct RelicStage {
  std::string name;
  std::shared_ptr<const reflect::RenderScene> scene;  // the relic's ray scenes (BVH)
  std::shared_ptr<reflect::PrefilteredIbl> ibl;       // the hall's, maybe shared with other stages
  double build_ms = 0;                                // what building it took
};

// Builds the stage of `relic` on `hall` (its panorama, yaw and proxy). Thread-safe (touches no
// loop): the kiosk builds the next relic's while the current one shows. `reuse`: a stage whose IBL
// is shared when the hall is the same (panorama pixels, yaw and proxy), instead of prefiltered
// again. Throws InputError for a bad panorama.
RelicStage buildStage(const std::string& name, const Model& relic, const cv::Mat& panorama, float yaw,
                      const reflect::PanoramaProxy& proxy, const RelicStage* reuse = nullptr);

class FrameLoop {
 public:
  // Opens the installation's cameras, learns the background, builds the IBL and the renderers
  // (options.scene, .relic and .config are not used: they name the installation its builder,
  // simulated::installationFor, makes). Throws InputError for a bad installation or settings.
  // `presenter` may be null (benchmarks: render without showing).
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
  // Forgets every camera's background and learns it again from the cameras' next frames, as many
  // as the installation's background_frames (kRelearnFrames when it has none); those frames show
  // the relic without visitors. Waits for the worker's frame in flight first.
  void relearnBackground();
  static constexpr int kRelearnFrames = 30;
  // While on, step() keeps a copy of every camera's colour image (cameraColour): the console's
  // snapshots. Off, it costs nothing.
  void keepCameraImages(bool keep) { keep_camera_images_ = keep; }
  // Per camera, its colour image of the last step() while keepCameraImages was on (8-bit BGR,
  // copies nobody writes to; empty where the camera gave none).
  const std::vector<cv::Mat>& cameraColour() const { return camera_colour_; }
  // Closes the presenter's outputs (the MP4 is renamed into place).
  void finish();
  // The relic shown from the next frame on (see above); the stage the loop started with is
  // stage(). The exposure is chosen again unless the tracer settings fix it.
  void setStage(RelicStage stage);
  const RelicStage& stage() const { return stage_; }
  // The relic's turn from the next frame on, radians counter-clockwise seen from above; nullopt:
  // not a turntable relic (framed by its box as without a playlist).
  void setTurn(std::optional<float> angle_rad);
  // From the next frame on, each presented face is (1 - weight) * from + weight * the frame's own;
  // weight >= 1 or empty faces: the frame alone.
  void setCrossfade(const display::FaceImages& from, float weight);

  const std::string& installationName() const { return installation_name_; }
  // The face views' side at full quality, pixels (resolved from the screen when so configured).
  int viewSize() const { return full_view_size_; }
  double cameraFps() const { return fps_; }
  const std::vector<CameraModel>& cameras() const { return cameras_; }
  std::vector<CameraModel> faceViews() const;  // the four views of the last frame
  const reflect::FrameResult& lastResult() const { return last_result_; }
  std::vector<capture::CameraHealth> cameraHealth() const;
  CameraFrameCounts cameraFrameCounts() const;
  display::QuadViewPresenter* presenter() { return presenter_.get(); }
  const reflect::RenderScene& renderScene() const { return *stage_.scene; }
  const reflect::PrefilteredIbl& ibl() const { return *stage_.ibl; }

 private:
  void learnBackground(const Installation& installation);
  // Acquisition and the foreground stage of one frame (on the loop's worker when overlapped).
  struct ForegroundFrame {
    std::vector<RgbdFrame> frames;  // per camera; empty where a camera gave none
    bool cameras_ended = false;     // every camera's stream has ended
    depthfilter::ForegroundCloud cloud;
    std::vector<cv::Mat> masks;  // per camera, copied from the pipeline; empty: no image
    int cameras_live = 0;
    double camera_skew_ms = -1;  // FrameReport::camera_skew_ms
    double acquisition_ms = 0, foreground_ms = 0;
    Clock::time_point acquired_at, done_at;  // FrameReport's acquired_at, foreground_done_at
    StageCpu cpu;                            // FrameReport::foreground_cpu
  };
  ForegroundFrame runForeground();
  void startNextForeground();  // runForeground() on the worker (overlap)
  std::vector<reflect::ForegroundCameraImage> cameraImages(const std::vector<RgbdFrame>& frames,
                                                           const std::vector<cv::Mat>& masks);
  // The stages of step() after the foreground, in order; each adds its times to `report`.
  std::vector<CameraModel> trackEyes(FrameReport& report);
  void render(const ForegroundFrame& fg, const std::vector<CameraModel>& views, FrameReport& report);
  void fixExposure();
  void present(FrameReport& report);
  // The frame's inputs seen from the turned relic (setTurn): world -> the unturned relic's frame.
  mat4 worldToRelic() const;

  FrameLoopOptions options_;
  int full_view_size_ = 0;  // options_.view_size as constructed; setQuality lowers options_'s
  std::string installation_name_;
  bool simulated_cameras_ = false;
  double fps_ = 30.0;
  std::vector<CameraModel> cameras_;
  std::unique_ptr<CameraAcquisition> acquisition_;
  std::future<ForegroundFrame> next_foreground_;  // overlap: the next frame's, in flight
  std::vector<cv::Mat> linear_colour_;            // per camera, reused: the pyramids copy what they keep
  std::vector<reflect::ForegroundCameraImage> last_images_;  // the last frame's, for renderReference
  depthfilter::ForegroundPipeline foreground_;
  depthfilter::ForegroundCloud cloud_;
  float camera_exposure_ = 1.0f;    // the cameras': radiance = srgbToLinear(colour) / exposure
  std::vector<vec3> colour_gains_;  // per camera, linear RGB (Installation::colour_gains)
  RelicStage stage_;
  std::unique_ptr<reflect::FrameRenderer> renderer_;
  float configured_exposure_ = 0.0f;  // options_.tracer.exposure as given (<= 0: automatic)
  std::optional<float> turn_;         // setTurn's
  display::FaceImages crossfade_from_;
  float crossfade_weight_ = 1.0f;
  display::EyeTracker eye_tracker_;
  std::unique_ptr<display::QuadViewPresenter> presenter_;
  std::array<vec3, 4> eyes_{};
  std::optional<float> exposure_;  // fixed after the first frame so the image does not pump
  reflect::FrameResult last_result_;
  std::int64_t index_ = 0;
  std::int64_t dropped_before_ = 0;      // mailbox drops counted up to the previous step
  int relearn_frames_ = kRelearnFrames;  // the installation's background_frames, when it has some
  int relearn_left_ = 0;                 // frames still to learn from; runForeground's
  bool keep_camera_images_ = false;
  std::vector<cv::Mat> camera_colour_;
};

}  // namespace holo::pipeline
