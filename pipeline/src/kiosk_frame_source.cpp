#include "holo/pipeline/kiosk_frame_source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "holo/capture/camera_power.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"
#include "holo/kiosk/fault_injector.hpp"
#include "holo/pipeline/frame_loop.hpp"

namespace holo::pipeline {
namespace {

// Black faces. Empty images would not do: the presenter keeps showing a face's last image when
// it gets none (a late renderer must not flash black), so blanking needs real black pixels.
display::FaceImages blackFaces() {
  display::FaceImages faces;
  for (cv::Mat& face : faces) face = cv::Mat::zeros(16, 16, CV_8UC3);
  return faces;
}

// Reads the presented picture back and reports the fault the kiosk exists to prevent (a black
// screen while the museum is open) and its opposite (a picture left on while it is closed).
void checkPicture(display::QuadViewPresenter& presenter, bool blank, kiosk::FrameReport& report) {
  cv::Mat grey;
  cv::cvtColor(presenter.readBack(), grey, cv::COLOR_BGR2GRAY);
  const bool black = cv::countNonZero(grey) == 0;
  if (!blank && black) report.errors.push_back("black frame presented during opening hours");
  if (blank && !black) report.errors.push_back("picture shown outside opening hours");
}

// The console's actions the frame source cannot act on are said once each in the log.
void noPlaylist(const kiosk::FrameRequest& request) {
  for (const kiosk::KioskAction action : request.actions)
    if (action == kiosk::KioskAction::NextRelic)
      HOLO_LOG_WARN("next-relic: this frame source has no exhibit playlist; nothing to change to");
}

// The stand-in frame source: the four faces' test pattern, presented for real. Headless, every
// 30th frame and every blanked one is read back and checked (checkPicture).
class TestPatternSource {
 public:
  TestPatternSource(const display::DisplayConfig& config, bool headless)
      : presenter_(headless ? display::makeHeadlessPresenter(config) : display::makeWindowPresenter(config)),
        headless_(headless),
        faults_(std::make_shared<kiosk::FaultInjector>(kiosk::FaultInjector::fromEnvironment())) {}

  kiosk::FrameReport operator()(const kiosk::FrameRequest& request) {
    kiosk::FrameReport report;
    Stopwatch stage;
    const kiosk::InjectedFaults faults = faults_->beginFrame(request.index, request.quality, request.blank);
    noPlaylist(request);
    for (const kiosk::KioskAction action : request.actions)
      if (action == kiosk::KioskAction::RelearnBackground)
        HOLO_LOG_WARN("relearn-background: the test pattern has no cameras");
    display::FaceImages faces = blackFaces();
    if (!request.blank && !faults.black) {
      // Lower quality levels halve the view resolution, as the real renderer will.
      const int side = std::max(40, 320 >> request.quality);
      if (pattern_side_ != side) {
        for (int f = 0; f < display::kFaceCount; ++f)
          patterns_[static_cast<std::size_t>(f)] = display::testPatternFace(f, {side, side});
        pattern_side_ = side;
      }
      faces = patterns_;
    }
    report.stage_ms["render"] = stage.ms();
    stage.restart();
    presenter_->present(faces);
    report.stage_ms["present"] = stage.ms();
    report.presented = presenter_->isOpen();
    if (request.snapshot) {  // images nobody writes to: the patterns are replaced, never redrawn
      report.snapshot.emplace();
      std::copy(faces.begin(), faces.end(), report.snapshot->faces.begin());
    }
    if (!report.presented) report.errors.push_back("display window closed");
    if (headless_ && (request.blank || request.index % 30 == 0))
      checkPicture(*presenter_, request.blank, report);
    return report;
  }

 private:
  std::shared_ptr<display::QuadViewPresenter> presenter_;  // shared: RenderFrame is copyable
  bool headless_;
  std::shared_ptr<kiosk::FaultInjector> faults_;
  display::FaceImages patterns_;
  int pattern_side_ = 0;
};

// The product: the live frame loop on the installation (the configured cameras, or the simulated
// museum), at the view size and camera mode the degradation policy asks for.
// Headless, every frame is read back and checked (checkPicture). Injected faults (tests, soak runs)
// act on the real pipeline: `camera_off` switches a simulated camera off, so its capture thread
// loses it and the frame loop drops it as stale, exactly as with a pulled cable.
class PipelineSource {
 public:
  PipelineSource(const display::DisplayConfig& config, bool headless, Installation installation,
                 int view_size)
      : headless_(headless),
        faults_(std::make_shared<kiosk::FaultInjector>(kiosk::FaultInjector::fromEnvironment())) {
    FrameLoopOptions options;
    options.live = true;
    options.view_size = view_size;
    full_view_size_ = options.view_size;
    loop_ = std::make_shared<FrameLoop>(
        options, std::move(installation),
        headless ? display::makeHeadlessPresenter(config) : display::makeWindowPresenter(config));
    for (const CameraModel& camera : loop_->cameras())
      camera_pixels_ += static_cast<double>(camera.width()) * camera.height();
    was_alive_.assign(loop_->cameras().size(), true);
    // A source made on reload inherits cameras a fault switched off, so the fault file can still
    // switch them on.
    for (int i = 0; i < static_cast<int>(loop_->cameras().size()); ++i)
      if (!capture::cameraPowered(i)) cameras_off_.push_back(i);
  }

  kiosk::FrameReport operator()(const kiosk::FrameRequest& request) {
    kiosk::FrameReport report;
    const kiosk::InjectedFaults faults = faults_->beginFrame(request.index, request.quality, request.blank);
    if (faults_->active()) switchCameras(faults.cameras_off, report);
    noPlaylist(request);
    for (const kiosk::KioskAction action : request.actions)
      if (action == kiosk::KioskAction::RelearnBackground) loop_->relearnBackground();
    if (request.blank) {
      if (request.snapshot) report.snapshot.emplace();  // black faces, no cameras
      loop_->presenter()->present(blackFaces());
      report.presented = loop_->presenter()->isOpen();
      if (headless_) checkPicture(*loop_->presenter(), true, report);
      return report;
    }
    // Each quality level below the best renders views 1.25x smaller (0.64x the pixels).
    const int view_size = std::max(std::min(64, full_view_size_),
                                   static_cast<int>(full_view_size_ / std::pow(1.25, request.quality)));
    loop_->setQuality(view_size, request.mode != kiosk::RenderMode::IblOnly);
    loop_->keepCameraImages(request.snapshot);
    const FrameReport frame = loop_->step();
    if (faults.black) loop_->presenter()->present(blackFaces());  // a broken source: black over it
    if (request.snapshot) {
      report.snapshot.emplace();
      const auto& views = loop_->lastResult().views;
      for (std::size_t f = 0; f < views.size() && f < report.snapshot->faces.size(); ++f)
        report.snapshot->faces[f] = faults.black ? blackFaces()[f] : views[f].display.clone();
      report.snapshot->cameras = loop_->cameraColour();
    }
    report.presented = frame.presented;
    report.stage_ms = {
        {"acquisition", frame.times.acquisition},     {"foreground", frame.times.foreground},
        {"dynamic_reflections", frame.times.dynamic}, {"static_reflections", frame.times.statics},
        {"composition", frame.times.composition},     {"display", frame.times.display}};
    // Foreground points are at most one per camera pixel.
    report.foreground_share =
        camera_pixels_ > 0 ? std::min(1.0, static_cast<double>(frame.foreground_points) / camera_pixels_)
                           : 0.0;
    if (frame.camera_skew_ms >= 0) report.camera_skew_ms = frame.camera_skew_ms;
    const std::vector<capture::CameraHealth> health = loop_->cameraHealth();
    for (std::size_t i = 0; i < health.size(); ++i) {
      kiosk::CameraHealth camera;
      camera.name = "camera " + std::to_string(i);
      camera.alive =
          health[i].connected && health[i].last_frame_age_s >= 0 && health[i].last_frame_age_s < 1.0;
      camera.frames = health[i].frames_completed;
      camera.dropped = health[i].frames_failed + health[i].frames_incomplete + health[i].frames_timed_out;
      camera.reconnects = health[i].reconnects;
      camera.last_frame_age_s = health[i].last_frame_age_s;
      camera.unpaired = health[i].frames_unpaired;
      camera.pair_skew_ms = health[i].pair_skew_ms;
      // Each loss and each return, once, named: the mode change alone does not say which camera.
      if (i < was_alive_.size() && camera.alive != was_alive_[i]) {
        if (camera.alive)
          report.errors.push_back(fmt::format("{} back ({} reconnects)", camera.name, camera.reconnects));
        else if (camera.last_frame_age_s < 0)
          report.errors.push_back(camera.name + " lost: no frame yet");
        else
          report.errors.push_back(
              fmt::format("{} lost: no frame for {:.1f} s", camera.name, camera.last_frame_age_s));
        was_alive_[i] = camera.alive;
      }
      report.cameras.push_back(camera);
    }
    if (!report.presented) report.errors.push_back("display window closed");
    if (headless_) checkPicture(*loop_->presenter(), false, report);
    return report;
  }

 private:
  void switchCameras(const std::vector<int>& off, kiosk::FrameReport& report) {
    if (off == cameras_off_) return;
    for (int i = 0; i < static_cast<int>(loop_->cameras().size()); ++i) {
      const bool now_off = std::find(off.begin(), off.end(), i) != off.end();
      const bool was_off = std::find(cameras_off_.begin(), cameras_off_.end(), i) != cameras_off_.end();
      if (now_off == was_off) continue;
      capture::setCameraPowered(i, !now_off);
      report.errors.push_back("injected fault: camera " + std::to_string(i) +
                              (now_off ? " switched off" : " switched on"));
    }
    for (const int i : off)
      if (i < 0 || i >= static_cast<int>(loop_->cameras().size()))
        HOLO_LOG_WARN("test faults: no camera {} to switch off", i);
    cameras_off_ = off;
  }

  std::shared_ptr<FrameLoop> loop_;  // shared: RenderFrame is copyable
  bool headless_;
  std::shared_ptr<kiosk::FaultInjector> faults_;
  int full_view_size_ = 320;
  double camera_pixels_ = 0;     // all cameras together
  std::vector<bool> was_alive_;  // per camera, as last reported
  std::vector<int> cameras_off_;
};

}  // namespace

kiosk::RenderFrame pipelineFrameSource(const display::DisplayConfig& config, bool headless,
                                       Installation installation, int view_size) {
  return PipelineSource(config, headless, std::move(installation), view_size);
}

kiosk::RenderFrame testPatternFrameSource(const display::DisplayConfig& config, bool headless) {
  return TestPatternSource(config, headless);
}

}  // namespace holo::pipeline
