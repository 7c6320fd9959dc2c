#include "holo/pipeline/frame_loop.hpp"

#include <tbb/parallel_for.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <opencv2/imgproc.hpp>

#include "camera_acquisition.hpp"
#include "frame_statistics.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/reflect/view.hpp"

namespace holo::pipeline {

reflect::TracerSettings liveTracerSettings() {
  reflect::TracerSettings settings;
  settings.aa_samples = 1;
  settings.edge_aa = true;
  settings.static_reuse_distance = 0.01f;
  settings.static_retraces_per_frame = 1;
  settings.static_defer_distance = 0.05f;
  return settings;
}

void setAntiAliasing(reflect::TracerSettings& tracer, reflect::AntiAliasing mode) {
  tracer.aa_samples = mode == reflect::AntiAliasing::Full ? 4 : 1;
  tracer.edge_aa = mode == reflect::AntiAliasing::Edges;
}

RelicStage buildStage(const std::string& name, const Model& relic, const cv::Mat& panorama, float yaw,
                      const reflect::PanoramaProxy& proxy, const RelicStage* reuse) {
  const auto t0 = Clock::now();
  RelicStage stage;
  stage.name = name;
  stage.scene = std::make_shared<const reflect::RenderScene>(relic, std::vector<Model>{});
  const reflect::Environment environment(panorama, yaw, proxy);
  if (reuse && reuse->ibl && reuse->ibl->sourceHash() == environment.contentHash())
    stage.ibl = reuse->ibl;
  else
    stage.ibl = std::make_shared<reflect::PrefilteredIbl>(environment);
  stage.build_ms = msSince(t0);
  return stage;
}

FrameLoop::FrameLoop(FrameLoopOptions options, Installation installation,
                     std::unique_ptr<display::QuadViewPresenter> presenter)
    : options_(std::move(options)),
      installation_name_(installation.name),
      simulated_cameras_(installation.simulated_cameras),
      fps_(installation.fps),
      cameras_(installation.cameras),
      foreground_([&] {
        if (installation.cameras.empty())
          throw InputError(installation.name, "cameras", "at least one camera");
        depthfilter::ForegroundPipelineConfig config;
        config.exposure = installation.camera_exposure;
        config.colour_gains = installation.colour_gains;
        config.filter = installation.depth_filter;
        config.cross_camera = installation.cross_camera_fill;
        config.mask = installation.foreground_mask;
        config.scale = installation.foreground_scale;
        config.full_size_outline = installation.foreground_full_size_outline;
        return depthfilter::ForegroundPipeline(installation.cameras, config);
      }()),
      camera_exposure_(installation.camera_exposure),
      colour_gains_(installation.colour_gains),
      eye_tracker_(options_.eyes),
      presenter_(std::move(presenter)) {
  if (options_.view_size == kViewSizeFromScreen) {
    if (!presenter_)
      throw InputError("frame loop", "view_size", "a pixel count when there is no screen to take it from",
                       "from the screen");
    options_.view_size = display::screenFaceViewPixels(*presenter_);
  }
  full_view_size_ = options_.view_size;
  if (options_.view_size < 16 || options_.view_size > 4096)
    throw InputError("frame loop", "view_size", "16..4096 pixels", std::to_string(options_.view_size));
  if (!(options_.fresh_frame_wait_ms >= 0.0 && options_.fresh_frame_wait_ms <= 1000.0))
    throw InputError("frame loop", "fresh_frame_wait_ms", "0..1000 milliseconds",
                     std::to_string(options_.fresh_frame_wait_ms));
  const std::size_t n = cameras_.size();
  if (installation.sources.size() != n || installation.capture_options.size() != n)
    throw Error("installation " + installation.name + ": one source and capture setting per camera expected");

  configured_exposure_ = options_.tracer.exposure;
  if (installation.plinth) options_.tracer.plinth = installation.plinth;
  stage_ = buildStage(installation.relic_name, installation.relic, installation.panorama,
                      installation.panorama_yaw_rad,
                      options_.panorama_at_infinity ? reflect::PanoramaProxy{} : installation.panorama_proxy);
  renderer_ = std::make_unique<reflect::FrameRenderer>(*stage_.scene, *stage_.ibl, options_.tracer);
  for (int f = 0; f < 4; ++f) eyes_[static_cast<std::size_t>(f)] = display::defaultEye(f, options_.eyes);

  // The cameras start once everything they feed is built.
  acquisition_ = std::make_unique<CameraAcquisition>(
      installation, options_.live, options_.stale_camera_s,
      std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double, std::milli>(options_.fresh_frame_wait_ms)));
  learnBackground(installation);
  acquisition_->preload(options_.preload_frames);
  HOLO_LOG_INFO("frame loop ready: {}, {} cameras, {} mode, views {}x{}", installation_name_, n,
                options_.live ? "live" : "deterministic", options_.view_size, options_.view_size);
}

FrameLoop::~FrameLoop() {
  // The worker uses the cameras: it finishes before they stop.
  if (next_foreground_.valid()) next_foreground_.wait();
  acquisition_.reset();
}

void FrameLoop::relearnBackground() {
  // The worker may be processing the next frame with the pipeline right now.
  waitForWorker();
  foreground_.forgetBackground();
  relearn_left_ = relearn_frames_;
  HOLO_LOG_INFO("relearning the background from the next {} frames of every camera", relearn_left_);
}

void FrameLoop::learnBackground(const Installation& installation) {
  if (installation.background_frames > 0) relearn_frames_ = installation.background_frames;
  // The background gamma_s each camera learns its mask against (docs/architecture.md, live frame step 2).
  // The calibration's background is depth as the cameras measured it: corrected like every frame.
  if (!installation.background.empty()) {
    std::vector<RgbdFrame> background = installation.background;
    acquisition_->correctDepth(background);
    foreground_.learnBackground(background);
  }
  if (installation.background_frames <= 0) return;
  ProgressReporter progress(installation.background_frames, "learning the background");
  for (int k = 0; k < installation.background_frames; ++k) {
    foreground_.learnBackground(acquisition_->backgroundFrame());
    progress.update(1);
  }
  progress.done();
}

std::vector<reflect::ForegroundCameraImage> FrameLoop::cameraImages(const std::vector<RgbdFrame>& frames,
                                                                    const std::vector<cv::Mat>& masks) {
  // sRGB bytes -> linear radiance in one table read per channel (the camera's exposure and
  // colour gains folded in).
  std::array<float, 256> linear_table{};
  for (int i = 0; i < 256; ++i)
    linear_table[std::size_t(i)] = srgbToLinear(float(i) / 255.0f) / camera_exposure_;
  linear_colour_.resize(frames.size());
  std::vector<reflect::ForegroundCameraImage> images(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (masks[i].empty() || frames[i].colour.empty()) continue;  // no image: its points are ignored
    const vec3 gains = i < colour_gains_.size() ? colour_gains_[i] : vec3(1.0f);
    // BGR order, as the bytes are.
    std::array<std::array<float, 256>, 3> table{};
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t k = 0; k < 256; ++k) table[c][k] = linear_table[k] * gains[2 - static_cast<int>(c)];
    const cv::Mat& srgb = frames[i].colour;
    cv::Mat& linear = linear_colour_[i];
    linear.create(srgb.size(), CV_32FC3);
    // The renderer reads the colour only inside the mask's box (ForegroundCameraImage): a
    // visitor converts a part of the frame, not all of it.
    const cv::Rect box =
        masks[i].type() == CV_8UC1 ? cv::boundingRect(masks[i]) : cv::Rect(0, 0, srgb.cols, srgb.rows);
    tbb::parallel_for(box.y, box.y + box.height, [&](int y) {
      const std::uint8_t* in = srgb.ptr<std::uint8_t>(y) + 3 * box.x;
      float* out = linear.ptr<float>(y) + 3 * box.x;
      for (int k = 0; k < 3 * box.width; ++k) out[k] = table[std::size_t(k % 3)][in[k]];
    });
    images[i].camera = cameras_[i];
    images[i].colour_bgr = linear;
    images[i].mask = masks[i];
  }
  return images;
}

FrameLoop::ForegroundFrame FrameLoop::runForeground() {
  ForegroundFrame out;
  const StageCpuClock cpu;
  CameraAcquisition::Frames acquired = acquisition_->next();
  out.acquired_at = acquired.taken_at;
  out.frames = std::move(acquired.frames);
  out.cameras_ended = acquired.ended;
  out.acquisition_ms = acquired.wait_ms;
  const CameraArrival arrival = cameraArrival(out.frames);
  out.cameras_live = arrival.live;
  out.camera_skew_ms = arrival.skew_ms;
  if (out.cameras_ended && out.cameras_live == 0) return out;  // nothing more will come
  const auto t0 = Clock::now();
  if (relearn_left_ > 0) {  // the background again: these frames have no foreground
    foreground_.learnBackground(out.frames);
    if (--relearn_left_ == 0) HOLO_LOG_INFO("background learnt again");
    out.masks.resize(out.frames.size());
    out.done_at = Clock::now();
    out.foreground_ms = msSince(t0);
    out.cpu = cpu.stop();
    return out;
  }
  out.cloud = foreground_.process(out.frames);
  // The pipeline overwrites its results with the next frame's, which may be processed while this
  // one is rendered: the renderer gets copies of the masks.
  out.masks.resize(out.frames.size());
  for (std::size_t i = 0; i < out.masks.size(); ++i) {
    const depthfilter::CameraForeground& result = foreground_.lastResult(i);
    if (!result.present || out.frames[i].colour.empty()) continue;
    // The renderer reads the masks at the cameras' resolution, the foreground's may be reduced.
    const cv::Size camera_size = out.frames[i].colour.size();
    out.masks[i] = result.mask.size() == camera_size ? result.mask.clone()
                                                     : depthfilter::expandedToFull(result.mask, camera_size);
  }
  out.done_at = Clock::now();
  out.foreground_ms = msSince(t0);
  out.cpu = cpu.stop();
  return out;
}

FrameReport FrameLoop::step() {
  FrameReport report;
  report.index = index_;
  const auto frame_start = Clock::now();

  // This frame's foreground: computed on the worker during the previous frame (overlap), else now.
  ForegroundFrame fg = next_foreground_.valid() ? next_foreground_.get() : runForeground();
  report.times.pipeline_wait = msSince(frame_start);
  report.times.acquisition = fg.acquisition_ms;
  report.cameras_live = fg.cameras_live;
  report.camera_skew_ms = fg.camera_skew_ms;
  report.acquired_at = fg.acquired_at;
  report.foreground_done_at = fg.done_at;
  report.foreground_cpu = fg.cpu;
  for (const RgbdFrame& frame : fg.frames) {
    report.camera_arrivals.push_back(frame.colour.empty() ? std::nullopt : std::optional(frame.host_time));
    report.camera_sequences.push_back(frame.colour.empty() ? std::nullopt : std::optional(frame.sequence));
  }
  if (fg.cameras_ended && fg.cameras_live == 0) {  // nothing more will come: no frame to render
    report.cameras_ended = true;
    return report;
  }
  report.rendering_started_at = Clock::now();
  const StageCpuClock rendering_cpu;
  // Deterministic: the next frame's camera frames are fixed, so its foreground runs while this
  // frame renders.
  if (options_.overlap && !options_.live) startNextForeground();

  if (keep_camera_images_) {
    camera_colour_.assign(fg.frames.size(), cv::Mat());
    for (std::size_t i = 0; i < fg.frames.size(); ++i) camera_colour_[i] = fg.frames[i].colour.clone();
  }
  cloud_ = std::move(fg.cloud);
  cloud_.sequence = index_;
  cloud_.time_s = static_cast<double>(index_) / fps_;
  report.foreground_points = cloud_.points.size();
  report.times.foreground = fg.foreground_ms;

  const std::vector<CameraModel> views = trackEyes(report);
  render(fg, views, report);
  report.rendering_done_at = Clock::now();
  report.rendering_cpu = rendering_cpu.stop();
  const CameraFrameCounts counts = cameraFrameCounts();
  report.dropped_frames = counts.dropped - dropped_before_;
  dropped_before_ = counts.dropped;
  addViewCounters(last_result_, report);
  fixExposure();
  // Live: the next frame's camera frames are taken only now, so that they are the newest when a
  // rendering can start with them (taken earlier they would wait through this rendering); its
  // foreground runs while this frame is presented (a window waits for the display there).
  if (options_.overlap && options_.live) startNextForeground();
  const StageCpuClock presenting_cpu;
  present(report);
  report.presenting_cpu = presenting_cpu.stop();
  report.times.total = msSince(frame_start);
  ++index_;
  return report;
}

void FrameLoop::startNextForeground() {
  next_foreground_ = std::async(std::launch::async, [this] { return runForeground(); });
}

std::vector<CameraModel> FrameLoop::trackEyes(FrameReport& report) {
  const auto t0 = Clock::now();
  if (options_.track_eyes) {
    const auto& eyes = eye_tracker_.update(cloud_);
    for (std::size_t f = 0; f < 4; ++f) {
      eyes_[f] = eyes[f].position;
      report.eyes_tracked[f] = eyes[f].tracked;
    }
  }
  std::vector<CameraModel> views = faceViews();
  report.times.display += msSince(t0);
  return views;
}

void FrameLoop::render(const ForegroundFrame& fg, const std::vector<CameraModel>& views,
                       FrameReport& report) {
  auto t0 = Clock::now();
  const bool foreground_passes = options_.tracer.foreground_enabled && !cloud_.empty();
  const std::vector<reflect::ForegroundCameraImage> images =
      foreground_passes ? cameraImages(fg.frames, fg.masks)
                        : std::vector<reflect::ForegroundCameraImage>(fg.frames.size());
  report.camera_images_ms = msSince(t0);
  report.times.dynamic += report.camera_images_ms;

  if (turn_ && *turn_ != 0.0f) {
    // The still relic traced from turned eyes, visitors and hall (see frame_loop.hpp).
    const mat4 T = worldToRelic();
    depthfilter::ForegroundCloud cloud = cloud_;
    for (depthfilter::ForegroundPoint& p : cloud.points) p.position = vec3(T * vec4(p.position, 1.0f));
    std::vector<reflect::ForegroundCameraImage> turned_images = images;
    for (reflect::ForegroundCameraImage& image : turned_images)
      image.camera.setPose(T * image.camera.T_world_camera());
    std::vector<CameraModel> turned_views = views;
    for (CameraModel& view : turned_views) view.setPose(T * view.T_world_camera());
    stage_.ibl->setRelicTurn(stage_.scene->relicBounds().center(), *turn_);
    last_result_ = renderer_->render(cloud, turned_images, turned_views);
    stage_.ibl->setRelicTurn(vec3(0.0f), 0.0f);  // a stage may share its IBL with the next
  } else {
    last_result_ = renderer_->render(cloud_, images, views);
  }
  last_images_ = images;
  addPassTimes(last_result_, report);
  t0 = Clock::now();
  report.non_finite_pixels = nonFinitePixels(last_result_);
  report.times.composition += msSince(t0);
  if (report.non_finite_pixels > 0)
    HOLO_LOG_WARN("frame {}: {} non-finite HDR pixels", index_, report.non_finite_pixels);
}

void FrameLoop::fixExposure() {
  // Fixed from the first frame's automatic choice, so the relic does not pump as visitors come
  // and go.
  if (!exposure_ && options_.tracer.exposure <= 0.0f && !last_result_.views.empty()) {
    std::vector<double> chosen;
    for (const reflect::ViewImages& v : last_result_.views) chosen.push_back(v.exposure);
    exposure_ = static_cast<float>(median(chosen));
    options_.tracer.exposure = *exposure_;
    renderer_->setExposure(*exposure_);
  }
}

void FrameLoop::present(FrameReport& report) {
  const auto t0 = Clock::now();
  if (presenter_) {
    display::FaceImages faces;
    display::FaceImages coverage;
    for (std::size_t f = 0; f < last_result_.views.size() && f < faces.size(); ++f) {
      faces[f] = last_result_.views[f].display;
      last_result_.views[f].coverage.convertTo(coverage[f], CV_8U, 255.0);
      const cv::Mat& from = crossfade_from_[f];
      if (crossfade_weight_ < 1.0f && !from.empty() && !faces[f].empty() && from.type() == faces[f].type()) {
        cv::Mat resized = from;
        if (from.size() != faces[f].size()) cv::resize(from, resized, faces[f].size(), 0, 0, cv::INTER_AREA);
        cv::Mat blended;
        cv::addWeighted(resized, 1.0 - crossfade_weight_, faces[f], crossfade_weight_, 0.0, blended);
        faces[f] = blended;
        // The outgoing relic's pixels are lit too: the light guide must not cut them off.
        cv::Mat grey;
        cv::cvtColor(resized, grey, cv::COLOR_BGR2GRAY);
        const cv::Mat lit = grey > 0;
        coverage[f] = cv::max(coverage[f], lit);
      }
    }
    presenter_->present(faces, &coverage);
    report.presented = presenter_->isOpen();
  }
  report.presented_at = Clock::now();
  report.times.display += msSince(t0);
}

void FrameLoop::waitForWorker() const {
  if (next_foreground_.valid()) next_foreground_.wait();
}

std::vector<CameraModel> FrameLoop::faceViews() const {
  Bounds3 bounds = stage_.scene->relicBounds();
  if (turn_ && !bounds.empty()) {
    // The box of the cylinder the turning relic sweeps: the same from every turn.
    const vec3 c = bounds.center();
    const vec3 h = 0.5f * bounds.extent();
    const float r = std::sqrt(h.x * h.x + h.z * h.z);
    bounds = Bounds3();
    bounds.extend(c - vec3(r, h.y, r));
    bounds.extend(c + vec3(r, h.y, r));
  }
  const vec3 target = bounds.empty() ? vec3(0.0f) : bounds.center();
  std::vector<CameraModel> views;
  for (const vec3& eye : eyes_)
    views.push_back(reflect::lookAtCamera(eye, target, reflect::framingFovDeg(eye, bounds),
                                          options_.view_size, options_.view_size));
  return views;
}

reflect::FrameResult FrameLoop::renderReference(reflect::TracerSettings settings) {
  settings.exposure = options_.tracer.exposure;
  reflect::FrameRenderer reference(*stage_.scene, *stage_.ibl, settings);
  return reference.render(cloud_, last_images_, faceViews());
}

void FrameLoop::setQuality(int view_size, bool foreground_enabled) {
  if (view_size == options_.view_size && foreground_enabled == options_.tracer.foreground_enabled) return;
  options_.view_size = std::clamp(view_size, 16, 4096);
  options_.tracer.foreground_enabled = foreground_enabled;
  renderer_ = std::make_unique<reflect::FrameRenderer>(*stage_.scene, *stage_.ibl, options_.tracer);
}

void FrameLoop::finish() {
  if (presenter_) presenter_->finish();
}

void FrameLoop::setStage(RelicStage stage) {
  if (!stage.scene || !stage.ibl) throw Error("frame loop: a relic stage without its scene or IBL");
  renderer_.reset();  // it refers to the old stage's scene and IBL
  stage_ = std::move(stage);
  exposure_.reset();
  options_.tracer.exposure = configured_exposure_;
  renderer_ = std::make_unique<reflect::FrameRenderer>(*stage_.scene, *stage_.ibl, options_.tracer);
}

void FrameLoop::setTurn(std::optional<float> angle_rad) {
  turn_ = angle_rad;
}

void FrameLoop::setCrossfade(const display::FaceImages& from, float weight) {
  crossfade_from_ = from;
  crossfade_weight_ = std::clamp(weight, 0.0f, 1.0f);
}

mat4 FrameLoop::worldToRelic() const {
  // Turning the relic by a about the vertical through its centre c is, for the still relic,
  // turning everything else by -a about that line.
  const vec3 c = stage_.scene->relicBounds().center();
  const float a = turn_.value_or(0.0f);
  return glm::translate(mat4(1.0f), c) * glm::rotate(mat4(1.0f), -a, vec3(0.0f, 1.0f, 0.0f)) *
         glm::translate(mat4(1.0f), -c);
}

std::vector<capture::CameraHealth> FrameLoop::cameraHealth() const {
  return acquisition_->cameraHealth(index_);
}

CameraFrameCounts FrameLoop::cameraFrameCounts() const {
  CameraFrameCounts counts = acquisition_->counts(index_);
  // Preloaded frames are simulated before the first step: the loop replays them from memory.
  counts.simulated = simulated_cameras_ && options_.preload_frames == 0;
  return counts;
}

}  // namespace holo::pipeline
