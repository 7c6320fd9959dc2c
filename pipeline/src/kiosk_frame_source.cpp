#include "holo/pipeline/kiosk_frame_source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
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
                 int view_size, PipelineSourceOptions source_options)
      : headless_(headless),
        faults_(std::make_shared<kiosk::FaultInjector>(kiosk::FaultInjector::fromEnvironment())),
        playlist_(std::make_shared<Playlist>()),
        source_options_(std::move(source_options)) {
    playlist_->relics = std::move(installation.playlist);
    playlist_->problems = std::move(installation.exhibit_problems);
    playlist_->first_name = installation.relic_name;
    FrameLoopOptions options;
    options.live = true;
    options.view_size = view_size;
    loop_ = std::make_shared<FrameLoop>(
        options, std::move(installation),
        headless ? display::makeHeadlessPresenter(config) : display::makeWindowPresenter(config));
    full_view_size_ = loop_->viewSize();
    for (const CameraModel& camera : loop_->cameras())
      camera_pixels_ += static_cast<double>(camera.width()) * camera.height();
    was_alive_.assign(loop_->cameras().size(), true);
    // A source made on reload inherits cameras a fault switched off, so the fault file can still
    // switch them on.
    for (int i = 0; i < static_cast<int>(loop_->cameras().size()); ++i)
      if (!capture::cameraPowered(i)) cameras_off_.push_back(i);
    playlist_->next = playlist_->relics.size() > 1 ? 1 : 0;
    playlist_->shown_since = std::chrono::steady_clock::now();
    startPreload();
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
      reportPlaylist(report);
      return report;
    }
    showPlaylist(request);
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
    reportPlaylist(report);
    return report;
  }

 private:
  using SteadyClock = std::chrono::steady_clock;
  // The playlist and where it stands; shared by the copies of the source.
  struct Playlist {
    std::vector<ExhibitRelic> relics;  // empty: the single relic of the installation
    std::vector<std::string> problems;
    std::string first_name;  // the single relic's name
    int current = 0;         // the entry on screen; -1: one a reload removed (still shown)
    int next = 0;            // the entry preload builds, shown after `current`
    bool switch_asked = false;
    SteadyClock::time_point shown_since;
    std::future<RelicStage> preload;  // the next entry's stage, being built
    display::FaceImages fade_from;    // the outgoing relic's last picture
    double fade_s = 0;
  };

  void startPreload() {
    Playlist& p = *playlist_;
    if (p.relics.size() < 2 && p.current >= 0) return;  // one relic: nothing to switch to
    const ExhibitRelic& entry = p.relics[static_cast<std::size_t>(p.next)];
    // Copies: a reload may replace the playlist while the worker builds.
    p.preload = std::async(std::launch::async, [entry, current = loop_->stage()] {
      return buildStage(entry.name, entry.relic, entry.panorama, entry.panorama_yaw_rad, entry.panorama_proxy,
                        &current);
    });
  }

  void switchRelic() {
    Playlist& p = *playlist_;
    const auto t0 = SteadyClock::now();
    RelicStage stage = p.preload.get();  // ready, or the options ask to wait
    const double wait_ms = std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
    const ExhibitRelic& incoming = p.relics[static_cast<std::size_t>(p.next)];
    p.fade_s = incoming.crossfade_s;
    p.fade_from = {};
    const reflect::FrameResult& last = loop_->lastResult();
    if (p.fade_s > 0)
      for (std::size_t f = 0; f < last.views.size() && f < p.fade_from.size(); ++f)
        p.fade_from[f] = last.views[f].display.clone();
    const double build_ms = stage.build_ms;
    const auto t1 = SteadyClock::now();
    loop_->setStage(std::move(stage));
    const double switch_ms = std::chrono::duration<double, std::milli>(SteadyClock::now() - t1).count();
    HOLO_LOG_INFO(
        "exhibit: now entry {} ({}); switched in {:.1f} ms on the loop's thread (+{:.1f} ms waiting "
        "for its stage, built in {:.0f} ms beside the previous relic)",
        incoming.index, incoming.name, switch_ms, wait_ms, build_ms);
    p.current = p.next;
    p.next = (p.current + 1) % static_cast<int>(p.relics.size());
    p.shown_since = SteadyClock::now();
    p.switch_asked = false;
    startPreload();
  }

  void takeReplacement() {
    if (!source_options_.control) return;
    std::optional<ExhibitControl::Replacement> replacement = source_options_.control->take();
    if (!replacement) return;
    Playlist& p = *playlist_;
    if (p.preload.valid()) p.preload.wait();  // it builds from the old playlist
    p.preload = {};
    p.relics = std::move(replacement->playlist);
    p.problems = std::move(replacement->problems);
    const std::string& shown = loop_->stage().name;
    const auto it = std::find_if(p.relics.begin(), p.relics.end(),
                                 [&](const ExhibitRelic& relic) { return relic.name == shown; });
    if (it != p.relics.end()) {
      p.current = static_cast<int>(it - p.relics.begin());
      p.next = (p.current + 1) % static_cast<int>(p.relics.size());
    } else {
      p.current = -1;
      p.next = 0;
      p.switch_asked = true;
    }
    HOLO_LOG_INFO("exhibit: playlist replaced, {} relics ({} left out)", p.relics.size(), p.problems.size());
    startPreload();
  }

  // Before a frame: the reload's playlist, the switch when the relic's time is up or one is asked
  // for, and the relic's turn and cross-fade for this frame.
  void showPlaylist(const kiosk::FrameRequest& request) {
    takeReplacement();
    Playlist& p = *playlist_;
    if (p.relics.empty()) return;
    for (const kiosk::KioskAction action : request.actions)
      if (action == kiosk::KioskAction::NextRelic) p.switch_asked = true;
    const double shown_s = std::chrono::duration<double>(SteadyClock::now() - p.shown_since).count();
    if (p.current >= 0 && shown_s >= p.relics[static_cast<std::size_t>(p.current)].duration_s)
      p.switch_asked = true;
    if (p.switch_asked && p.preload.valid() &&
        (source_options_.wait_for_next_relic ||
         p.preload.wait_for(std::chrono::seconds(0)) == std::future_status::ready))
      switchRelic();
    else if (p.switch_asked && p.relics.size() < 2)
      p.switch_asked = false;  // nothing else to show
    const double since_s = std::chrono::duration<double>(SteadyClock::now() - p.shown_since).count();
    const ExhibitRelic* shown = p.current >= 0 ? &p.relics[static_cast<std::size_t>(p.current)] : nullptr;
    if (shown && shown->turntable_deg_per_s != 0.0) {
      const double turns = shown->turntable_deg_per_s * since_s / 360.0;
      loop_->setTurn(static_cast<float>(2.0 * kPi * (turns - std::floor(turns))));
    } else {
      loop_->setTurn(std::nullopt);
    }
    const float weight = p.fade_s > 0 ? static_cast<float>(since_s / p.fade_s) : 1.0f;
    if (weight >= 1.0f && !p.fade_from[0].empty()) p.fade_from = {};
    loop_->setCrossfade(p.fade_from, weight);
  }

  void reportPlaylist(kiosk::FrameReport& report) const {
    const Playlist& p = *playlist_;
    report.relic = p.relics.empty() ? p.first_name : loop_->stage().name;
    if (!p.relics.empty()) report.next_relic = p.relics[static_cast<std::size_t>(p.next)].name;
    report.exhibit_problems = p.problems;
  }

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
  std::shared_ptr<Playlist> playlist_;
  PipelineSourceOptions source_options_;
};

}  // namespace

kiosk::RenderFrame pipelineFrameSource(const display::DisplayConfig& config, bool headless,
                                       Installation installation, int view_size,
                                       PipelineSourceOptions options) {
  return PipelineSource(config, headless, std::move(installation), view_size, std::move(options));
}

kiosk::RenderFrame testPatternFrameSource(const display::DisplayConfig& config, bool headless) {
  return TestPatternSource(config, headless);
}

}  // namespace holo::pipeline
