#include "holo/pipeline/frame_loop.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/log.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/reflect/view.hpp"

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

}  // namespace

reflect::TracerSettings liveTracerSettings() {
  reflect::TracerSettings settings;
  settings.aa_samples = 1;
  settings.edge_aa = true;
  settings.static_reuse_distance = 0.01f;
  // Off in the loop, on in the tracer's evaluation: at 25 fps on 2 cores the bounce's extra ray
  // per hit point (+6 ms a frame) does not fit; its (time, error) point is in docs/frame_loop.md
  // (`bench frame --interreflection --reference`).
  settings.relic_interreflection = false;
  return settings;
}

void setAntiAliasing(reflect::TracerSettings& tracer, reflect::AntiAliasing mode) {
  tracer.aa_samples = mode == reflect::AntiAliasing::Full ? 4 : 1;
  tracer.edge_aa = mode == reflect::AntiAliasing::Edges;
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
        return depthfilter::ForegroundPipeline(installation.cameras, config);
      }()),
      camera_exposure_(installation.camera_exposure),
      colour_gains_(installation.colour_gains),
      depth_correction_(installation.depth_correction),
      depth_to_colour_(installation.depth_to_colour),
      eye_tracker_(options_.eyes),
      presenter_(std::move(presenter)) {
  if (options_.view_size < 16 || options_.view_size > 4096)
    throw InputError("frame loop", "view_size", "16..4096 pixels", std::to_string(options_.view_size));
  const std::size_t n = cameras_.size();
  if (installation.sources.size() != n || installation.capture_options.size() != n)
    throw Error("installation " + installation.name + ": one source and capture setting per camera expected");

  environment_ = reflect::Environment(
      installation.panorama, installation.panorama_yaw_rad,
      options_.panorama_at_infinity ? reflect::PanoramaProxy{} : installation.panorama_proxy);
  ibl_ = reflect::PrefilteredIbl(environment_);
  render_scene_ = std::make_unique<reflect::RenderScene>(installation.relic, std::vector<Model>{});
  renderer_ = std::make_unique<reflect::FrameRenderer>(*render_scene_, ibl_, options_.tracer);
  for (int f = 0; f < 4; ++f) eyes_[static_cast<std::size_t>(f)] = display::defaultEye(f, options_.eyes);

  capture_options_ = installation.capture_options;
  rejected_.assign(n, std::string());
  if (options_.live) {
    latest_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      mailboxes_.push_back(std::make_unique<capture::LatestFrameMailbox>());
      threads_.push_back(std::make_unique<capture::CaptureThread>(std::move(installation.sources[i]),
                                                                  *mailboxes_.back(), capture_options_[i]));
    }
  } else {
    sources_ = std::move(installation.sources);
    source_ended_.assign(n, 0);
    for (auto& source : sources_) {
      source->open();
      source->start();
    }
  }
  learnBackground(installation);
  if (!options_.live) {
    for (int f = 0; f < options_.preload_frames; ++f) preloaded_.push_back(grabDeterministic());
  }
  HOLO_LOG_INFO("frame loop ready: {}, {} cameras, {} mode, views {}x{}", installation_name_, n,
                options_.live ? "live" : "deterministic", options_.view_size, options_.view_size);
}

FrameLoop::~FrameLoop() {
  if (next_foreground_.valid()) next_foreground_.wait();
  for (auto& thread : threads_) thread->stop();
  if (next_frames_.valid()) next_frames_.wait();
  for (auto& source : sources_) source->stop();
}

void FrameLoop::learnBackground(const Installation& installation) {
  // The background gamma_s each camera learns its mask against (docs/architecture.md, live frame step 2).
  // The calibration's background is depth as the cameras measured it: corrected like every frame.
  if (!installation.background.empty()) {
    std::vector<RgbdFrame> background = installation.background;
    correctDepth(background);
    foreground_.learnBackground(background);
  }
  if (installation.background_frames <= 0) return;
  ProgressReporter progress(installation.background_frames, "learning the background");
  for (int k = 0; k < installation.background_frames; ++k) {
    std::vector<RgbdFrame> frames = options_.live ? waitLive() : grabDeterministic().frames;
    correctDepth(frames);
    rejectUnusable(frames);
    foreground_.learnBackground(frames);
    progress.update(1);
  }
  progress.done();
}

RgbdFrame FrameLoop::grabFrom(std::size_t camera) {
  if (source_ended_[camera]) return {};
  capture::CameraSource& source = *sources_[camera];
  const capture::CaptureOptions& options = capture_options_[camera];
  const auto give_up = Clock::now() + options.silence_timeout;
  for (;;) {
    capture::GrabResult result = source.grab(options.grab_timeout);
    switch (result.status) {
      case capture::GrabStatus::Ok:
        result.frame.camera_id = static_cast<int>(camera);
        return std::move(result.frame);
      case capture::GrabStatus::EndOfStream:
        HOLO_LOG_INFO("camera {}: end of stream", source.name());
        source_ended_[camera] = 1;
        return {};
      case capture::GrabStatus::Disconnected:
        HOLO_LOG_WARN("camera {}: disconnected ({}); missing this frame", source.name(), result.message);
        return {};
      default:
        if (Clock::now() > give_up) {
          HOLO_LOG_WARN("camera {}: no frame within {} ms ({}); missing this frame", source.name(),
                        options.silence_timeout.count(), result.message);
          return {};
        }
    }
  }
}

FrameLoop::CameraFrames FrameLoop::grabDeterministic() {
  CameraFrames out;
  out.frames.resize(sources_.size());
  tbb::parallel_for(std::size_t(0), sources_.size(), [&](std::size_t i) { out.frames[i] = grabFrom(i); });
  out.ended = std::all_of(source_ended_.begin(), source_ended_.end(), [](std::uint8_t e) { return e != 0; });
  return out;
}

std::vector<RgbdFrame> FrameLoop::waitLive() {
  std::vector<RgbdFrame> frames(mailboxes_.size());
  for (std::size_t i = 0; i < mailboxes_.size(); ++i)
    if (!threads_[i]->finished())
      if (auto fresh = mailboxes_[i]->waitAndTake(capture_options_[i].silence_timeout))
        frames[i] = std::move(*fresh);
  return frames;
}

FrameLoop::CameraFrames FrameLoop::acquire(double& wait_ms) {
  const auto t0 = Clock::now();
  CameraFrames out;
  if (!options_.live) {
    // The preloaded frames first; then each frame's grab was started when the previous one was
    // taken (the first one is grabbed now).
    if (!preloaded_.empty()) {
      out = std::move(preloaded_.front());
      preloaded_.pop_front();
    } else {
      out = next_frames_.valid() ? next_frames_.get() : grabDeterministic();
      next_frames_ = std::async(std::launch::async, [this] { return grabDeterministic(); });
    }
  } else {
    const auto now = Clock::now();
    out.frames.resize(latest_.size());
    out.ended = true;
    for (std::size_t i = 0; i < latest_.size(); ++i) {
      if (auto fresh = mailboxes_[i]->take()) latest_[i] = std::move(*fresh);
      const bool stale =
          latest_[i].colour.empty() ||
          std::chrono::duration<double>(now - latest_[i].host_time).count() > options_.stale_camera_s;
      if (!stale) out.frames[i] = latest_[i];  // an empty frame tells the pipeline the camera is missing
      out.ended = out.ended && threads_[i]->finished() && !mailboxes_[i]->peekLatest();
    }
  }
  wait_ms = msSince(t0);
  return out;
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

void FrameLoop::correctDepth(std::vector<RgbdFrame>& frames) const {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    RgbdFrame& frame = frames[i];
    if (frame.depth.empty() || frame.depth.type() != CV_32FC1) continue;  // rejectUnusable says why
    // Into new buffers: the frame's depth may be shared (the live mailbox, preloaded frames).
    if (i < depth_correction_.size() && depth_correction_[i] != 1.0f) {
      cv::Mat corrected;
      frame.depth.convertTo(corrected, CV_32FC1, depth_correction_[i]);
      frame.depth = corrected;
    }
    if (i < depth_to_colour_.size() && depth_to_colour_[i] &&
        frame.depth.size() == depth_to_colour_[i]->depthSize())
      frame.depth = depth_to_colour_[i]->apply(frame.depth);
  }
}

void FrameLoop::rejectUnusable(std::vector<RgbdFrame>& frames) {
  for (std::size_t i = 0; i < frames.size() && i < cameras_.size(); ++i) {
    RgbdFrame& frame = frames[i];
    if (frame.colour.empty() && frame.depth.empty()) continue;  // missing, nothing to say
    const cv::Size size(cameras_[i].width(), cameras_[i].height());
    std::string problem;
    if (frame.colour.type() != CV_8UC3 || frame.colour.size() != size)
      problem = fmt::format("colour {}x{} type {} (expected {}x{} 8-bit BGR)", frame.colour.cols,
                            frame.colour.rows, frame.colour.type(), size.width, size.height);
    else if (frame.depth.type() != CV_32FC1 || frame.depth.size() != size)
      problem = fmt::format("depth {}x{} type {} (expected {}x{} float metres, as calibrated)",
                            frame.depth.cols, frame.depth.rows, frame.depth.type(), size.width, size.height);
    if (problem.empty()) continue;
    // Once per camera and kind of problem: a camera that keeps sending such frames is missing.
    if (rejected_[i] != problem)
      HOLO_LOG_WARN("camera {}: frame not usable, treated as missing: {}", i, problem);
    rejected_[i] = problem;
    ++rejected_frames_;
    frame = RgbdFrame{};
  }
}

FrameLoop::ForegroundFrame FrameLoop::runForeground() {
  ForegroundFrame out;
  out.acquired = acquire(out.acquisition_ms);
  correctDepth(out.acquired.frames);
  rejectUnusable(out.acquired.frames);
  std::optional<Clock::time_point> oldest, newest;
  for (const RgbdFrame& f : out.acquired.frames) {
    if (f.colour.empty()) continue;
    ++out.cameras_live;
    if (!oldest || f.host_time < *oldest) oldest = f.host_time;
    if (!newest || f.host_time > *newest) newest = f.host_time;
  }
  if (out.cameras_live >= 2)
    out.camera_skew_ms = std::chrono::duration<double, std::milli>(*newest - *oldest).count();
  if (out.acquired.ended && out.cameras_live == 0) return out;  // nothing more will come
  const auto t0 = Clock::now();
  out.cloud = foreground_.process(out.acquired.frames);
  // The pipeline overwrites its results with the next frame's, which may be processed while this
  // one is rendered: the renderer gets copies of the masks.
  out.masks.resize(out.acquired.frames.size());
  for (std::size_t i = 0; i < out.masks.size(); ++i) {
    const depthfilter::CameraForeground& result = foreground_.lastResult(i);
    if (result.present && !out.acquired.frames[i].colour.empty()) out.masks[i] = result.mask.clone();
  }
  out.foreground_ms = msSince(t0);
  return out;
}

FrameReport FrameLoop::step() {
  FrameReport report;
  report.index = index_;
  const auto frame_start = Clock::now();

  // This frame's foreground: computed while the previous frame was rendered (overlap), else now.
  ForegroundFrame fg = next_foreground_.valid() ? next_foreground_.get() : runForeground();
  report.times.pipeline_wait = msSince(frame_start);
  const std::vector<RgbdFrame>& frames = fg.acquired.frames;
  report.times.acquisition = fg.acquisition_ms;
  report.cameras_live = fg.cameras_live;
  report.camera_skew_ms = fg.camera_skew_ms;
  if (fg.acquired.ended && fg.cameras_live == 0) {  // nothing more will come: no frame to render
    report.cameras_ended = true;
    return report;
  }
  // The next frame's acquisition and foreground run on a worker while this one is rendered.
  if (options_.overlap) next_foreground_ = std::async(std::launch::async, [this] { return runForeground(); });

  cloud_ = std::move(fg.cloud);
  cloud_.sequence = index_;
  cloud_.time_s = static_cast<double>(index_) / fps_;
  report.foreground_points = cloud_.points.size();
  report.times.foreground = fg.foreground_ms;

  auto t0 = Clock::now();
  if (options_.track_eyes) {
    const auto& eyes = eye_tracker_.update(cloud_);
    for (std::size_t f = 0; f < 4; ++f) {
      eyes_[f] = eyes[f].position;
      report.eyes_tracked[f] = eyes[f].tracked;
    }
  }
  const std::vector<CameraModel> views = faceViews();
  const double eyes_ms = msSince(t0);

  t0 = Clock::now();
  const bool foreground_passes = options_.tracer.foreground_enabled && !cloud_.empty();
  const std::vector<reflect::ForegroundCameraImage> images =
      foreground_passes ? cameraImages(frames, fg.masks)
                        : std::vector<reflect::ForegroundCameraImage>(frames.size());
  report.camera_images_ms = msSince(t0);
  report.times.dynamic += report.camera_images_ms;

  last_result_ = renderer_->render(cloud_, images, views);
  last_images_ = images;
  for (const reflect::PassTiming& t : last_result_.frame_timings) report.pass_ms[std::size_t(t.pass)] += t.ms;
  for (const reflect::ViewImages& view : last_result_.views)
    for (const reflect::PassTiming& t : view.timings) report.pass_ms[std::size_t(t.pass)] += t.ms;
  report.times.foreground += passMs(last_result_.frame_timings, {reflect::Pass::VoxelGrid});
  report.times.dynamic += passMs(last_result_.frame_timings, {reflect::Pass::Pyramids});
  for (const reflect::ViewImages& view : last_result_.views) {
    report.times.dynamic +=
        passMs(view.timings, {reflect::Pass::ForegroundWalk, reflect::Pass::RefractedForeground});
    report.times.statics += passMs(view.timings, {reflect::Pass::HitPoints, reflect::Pass::StaticReflections,
                                                  reflect::Pass::Refraction, reflect::Pass::Clearcoat});
    report.times.composition += passMs(view.timings, {reflect::Pass::Composition, reflect::Pass::ToneMap});
  }
  t0 = Clock::now();
  for (const reflect::ViewImages& view : last_result_.views)
    report.non_finite_pixels += countNonFinite(view.hdr);
  report.times.composition += msSince(t0);
  if (report.non_finite_pixels > 0)
    HOLO_LOG_WARN("frame {}: {} non-finite HDR pixels", index_, report.non_finite_pixels);
  const CameraFrameCounts counts = cameraFrameCounts();
  report.dropped_frames = counts.dropped - dropped_before_;
  dropped_before_ = counts.dropped;
  report.plan = last_result_.plan.describe();
  for (const reflect::ViewImages& view : last_result_.views) {
    report.static_reused_views += view.static_reused ? 1 : 0;
    report.refined_pixels += view.refined_pixels;
    report.refraction_rays += view.refraction_rays;
    report.refracted_walks += view.refracted_walks;
    report.supersampled_samples += view.supersampled_samples;
    if (!view.coverage.empty())
      report.relic_pixels += static_cast<std::size_t>(cv::countNonZero(view.coverage));
  }

  // Exposure: fixed from the first frame's automatic choice, so the relic does not pump as
  // visitors come and go.
  if (!exposure_ && options_.tracer.exposure <= 0.0f && !last_result_.views.empty()) {
    std::vector<double> chosen;
    for (const reflect::ViewImages& v : last_result_.views) chosen.push_back(v.exposure);
    exposure_ = static_cast<float>(median(chosen));
    options_.tracer.exposure = *exposure_;
    renderer_->setExposure(*exposure_);
  }

  t0 = Clock::now();
  if (presenter_) {
    display::FaceImages faces;
    display::FaceImages coverage;
    for (std::size_t f = 0; f < last_result_.views.size() && f < faces.size(); ++f) {
      faces[f] = last_result_.views[f].display;
      last_result_.views[f].coverage.convertTo(coverage[f], CV_8U, 255.0);
    }
    presenter_->present(faces, &coverage);
    report.presented = presenter_->isOpen();
  }
  report.times.display = eyes_ms + msSince(t0);
  report.times.total = msSince(frame_start);
  ++index_;
  return report;
}

void FrameLoop::waitForWorker() const {
  if (next_foreground_.valid()) next_foreground_.wait();
}

std::vector<CameraModel> FrameLoop::faceViews() const {
  const Bounds3 bounds = render_scene_->relicBounds();
  const vec3 target = bounds.empty() ? vec3(0.0f) : bounds.center();
  std::vector<CameraModel> views;
  for (const vec3& eye : eyes_)
    views.push_back(reflect::lookAtCamera(eye, target, reflect::framingFovDeg(eye, bounds),
                                          options_.view_size, options_.view_size));
  return views;
}

reflect::FrameResult FrameLoop::renderReference(reflect::TracerSettings settings) {
  settings.exposure = options_.tracer.exposure;
  reflect::FrameRenderer reference(*render_scene_, ibl_, settings);
  return reference.render(cloud_, last_images_, faceViews());
}

void FrameLoop::setQuality(int view_size, bool foreground_enabled) {
  if (view_size == options_.view_size && foreground_enabled == options_.tracer.foreground_enabled) return;
  options_.view_size = std::clamp(view_size, 16, 4096);
  options_.tracer.foreground_enabled = foreground_enabled;
  renderer_ = std::make_unique<reflect::FrameRenderer>(*render_scene_, ibl_, options_.tracer);
}

void FrameLoop::finish() {
  if (presenter_) presenter_->finish();
}

std::vector<capture::CameraHealth> FrameLoop::cameraHealth() const {
  std::vector<capture::CameraHealth> health;
  for (const auto& thread : threads_) health.push_back(thread->health());
  if (threads_.empty())  // deterministic: the simulated cameras always deliver
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(cameras_.size()); ++i) {
      capture::CameraHealth h;
      h.connected = true;
      h.frames_completed = index_;
      h.last_frame_age_s = 0.0;
      health.push_back(h);
    }
  return health;
}

CameraFrameCounts FrameLoop::cameraFrameCounts() const {
  CameraFrameCounts counts;
  counts.live = options_.live;
  // Preloaded frames are simulated before the first step: the loop replays them from memory.
  counts.simulated = simulated_cameras_ && options_.preload_frames == 0;
  counts.rejected = rejected_frames_.load();
  if (!options_.live) {
    counts.produced = counts.consumed = index_ * static_cast<std::int64_t>(cameras_.size());
    return counts;
  }
  for (const auto& mailbox : mailboxes_) {
    const capture::MailboxCounts c = mailbox->counts();
    counts.produced += c.published;
    counts.consumed += c.taken;
    counts.dropped += c.dropped;
  }
  counts.unconsumed = counts.produced - counts.consumed;
  return counts;
}

StageTimes medianTimes(const std::vector<FrameReport>& reports) {
  auto pick = [&](double StageTimes::*field) {
    std::vector<double> values;
    for (const FrameReport& r : reports) values.push_back(r.times.*field);
    return median(values);
  };
  StageTimes m;
  m.acquisition = pick(&StageTimes::acquisition);
  m.foreground = pick(&StageTimes::foreground);
  m.dynamic = pick(&StageTimes::dynamic);
  m.statics = pick(&StageTimes::statics);
  m.composition = pick(&StageTimes::composition);
  m.display = pick(&StageTimes::display);
  m.total = pick(&StageTimes::total);
  m.pipeline_wait = pick(&StageTimes::pipeline_wait);
  return m;
}

std::vector<std::pair<std::string, double>> medianPasses(const std::vector<FrameReport>& reports) {
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t p = 0; p <= kPassCount; ++p) {
    std::vector<double> values;
    for (const FrameReport& r : reports) values.push_back(p < kPassCount ? r.pass_ms[p] : r.camera_images_ms);
    out.emplace_back(p < kPassCount ? reflect::passName(static_cast<reflect::Pass>(p)) : "CameraImages",
                     median(values));
  }
  return out;
}

std::int64_t totalNonFinite(const std::vector<FrameReport>& reports) {
  std::int64_t n = 0;
  for (const FrameReport& r : reports) n += r.non_finite_pixels;
  return n;
}

std::string formatTimingTable(const StageTimes& m, const std::vector<FrameReport>& reports,
                              const CameraFrameCounts& cameras) {
  std::string out;
  const auto row = [&out](const char* name, double ms) { out += fmt::format("{:<34} {:9.2f}\n", name, ms); };
  const auto fps = [](double ms) { return ms > 0 ? 1000.0 / ms : 0.0; };
  out += fmt::format("{:<34} median ms   (over {} frames)\n", "stage", reports.size());
  if (!cameras.simulated) row("acquisition (wait)", m.acquisition);
  row("foreground point cloud", m.foreground);
  row("dynamic reflections", m.dynamic);
  row("static reflections", m.statics);
  row("composition", m.composition);
  row("display", m.display);
  row("appliance stages, one after another", m.applianceStages());
  row("  frames per second, no overlap", fps(m.applianceStages()));
  if (cameras.simulated) {
    out += "simulating the cameras (no real installation pays this):\n";
    row("  acquisition (wait)", m.acquisition);
  }
  row("waiting for the foreground", m.pipeline_wait);
  row(cameras.simulated ? "whole frame, simulation included" : "whole frame", m.total);
  row("  frames per second", fps(m.total));
  if (cameras.simulated)
    out += "the appliance's own frame rate, cameras simulated before timing: holopyramid bench frame\n";
  out += fmt::format("{:<34} {:9}\n", "non-finite HDR pixels", totalNonFinite(reports));
  out += fmt::format(
      "camera frames ({}): {} produced, {} consumed, {} dropped, {} never consumed, {} unusable\n",
      cameras.live ? "live" : "deterministic: none dropped by construction", cameras.produced,
      cameras.consumed, cameras.dropped, cameras.unconsumed, cameras.rejected);
  return out;
}

std::string timingJson(const StageTimes& m, const std::vector<FrameReport>& reports,
                       const CameraFrameCounts& cameras) {
  auto stages = [](const StageTimes& t) {
    return nlohmann::json{{"acquisition_ms", t.acquisition},     {"foreground_ms", t.foreground},
                          {"dynamic_reflections_ms", t.dynamic}, {"static_reflections_ms", t.statics},
                          {"composition_ms", t.composition},     {"display_ms", t.display},
                          {"pipeline_wait_ms", t.pipeline_wait}, {"frame_ms", t.total}};
  };
  nlohmann::json j;
  j["frames"] = reports.size();
  j["stages_ms"] = stages(m);  // medians over the frames
  j["frame_ms"] = m.total;
  j["fps"] = m.total > 0 ? 1000.0 / m.total : 0.0;
  j["appliance_stages_ms"] = m.applianceStages();
  j["appliance_fps"] = m.applianceStages() > 0 ? 1000.0 / m.applianceStages() : 0.0;
  j["simulated_cameras"] = cameras.simulated;
  j["non_finite_pixels"] = totalNonFinite(reports);
  j["camera_frames"] = {{"mode", cameras.live ? "live" : "deterministic"},
                        {"produced", cameras.produced},
                        {"consumed", cameras.consumed},
                        {"dropped", cameras.dropped},
                        {"unconsumed", cameras.unconsumed},
                        {"rejected", cameras.rejected}};
  nlohmann::json per_frame = nlohmann::json::array();
  for (const FrameReport& r : reports) {
    nlohmann::json f = stages(r.times);
    f["index"] = r.index;
    f["foreground_points"] = r.foreground_points;
    f["cameras_live"] = r.cameras_live;
    f["plan"] = r.plan;
    f["non_finite_pixels"] = r.non_finite_pixels;
    f["dropped_frames"] = r.dropped_frames;
    f["static_reused_views"] = r.static_reused_views;
    f["refined_pixels"] = r.refined_pixels;
    f["relic_pixels"] = r.relic_pixels;
    f["refraction_rays"] = r.refraction_rays;
    f["refracted_walks"] = r.refracted_walks;
    f["supersampled_samples"] = r.supersampled_samples;
    nlohmann::json passes;
    for (std::size_t p = 0; p < kPassCount; ++p)
      passes[reflect::passName(static_cast<reflect::Pass>(p))] = r.pass_ms[p];
    passes["CameraImages"] = r.camera_images_ms;
    f["passes_ms"] = passes;
    per_frame.push_back(f);
  }
  j["per_frame"] = per_frame;
  return j.dump(2);
}

}  // namespace holo::pipeline
