#include "holo/kiosk/kiosk_loop.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/log_tail.hpp"
#include "holo/core/stats.hpp"
#include "holo/kiosk/listen_address.hpp"

namespace holo::kiosk {
namespace {
using Clock = std::chrono::steady_clock;
double msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
// Blanked monitors still get a black frame now and then, so the watchdog keeps seeing progress.
constexpr double kBlankFps = 2.0;
// Frames after a start or reload that the degradation policy does not see.
constexpr int kWarmupFrames = 5;
}  // namespace

KioskLoop::KioskLoop(LoadedConfig config, RenderFrame render, Reload reload)
    : config_(config), render_(std::move(render)), reload_(std::move(reload)), started_(Clock::now()) {
  applyConfig(std::move(config));
}

KioskLoop::~KioskLoop() {
  // The servers' threads call back into this object: they end before any member does.
  console_.reset();
  server_.reset();
}

void KioskLoop::applyConfig(LoadedConfig config) {
  const bool server_changed = !server_ || config.kiosk.health_address != config_.kiosk.health_address ||
                              config.kiosk.health_port != config_.kiosk.health_port;
  const bool console_changed = !console_ || config.kiosk.console.address != config_.kiosk.console.address ||
                               config.kiosk.console.port != config_.kiosk.console.port;
  config_ = std::move(config);
  policy_ = std::make_unique<DegradationPolicy>(config_.kiosk.degradation);
  warmup_frames_left_ = kWarmupFrames;
  {
    std::lock_guard lock(mutex_);
    health_.config_source = config_.source;
    health_.config_warning = config_.warning;
    if (!config_.warning.empty()) health_.addError(config_.warning);
    health_.quality = policy_->qualityName();
    health_.quality_level = policy_->quality();
    health_.frame_budget_ms = config_.kiosk.degradation.frame_budget_ms;
    health_.target_fps = std::min(config_.kiosk.max_fps, 1000.0 / config_.kiosk.degradation.frame_budget_ms);
  }
  applyConsole(console_changed);
  if (server_changed) {
    server_.reset();
    if (config_.kiosk.health_port < 0) return;
    try {
      server_ = std::make_unique<HealthServer>(config_.kiosk.health_address,
                                               static_cast<std::uint16_t>(config_.kiosk.health_port),
                                               [this] { return health(); });
      HOLO_LOG_INFO("health endpoint on http://{}:{}/health (and /metrics)", config_.kiosk.health_address,
                    server_->port());
    } catch (const std::exception& e) {
      // The picture matters more than the endpoint: report and keep going.
      HOLO_LOG_ERROR("health endpoint not started: {}", e.what());
      std::lock_guard lock(mutex_);
      health_.addError(std::string("health endpoint not started: ") + e.what());
    }
  }
}

void KioskLoop::applyConsole(bool listener_changed) {
  const ConsoleSettings& settings = config_.kiosk.console;
  if (!settings.enabled) {
    if (console_) HOLO_LOG_INFO("console switched off");
    console_.reset();
    console_auth_.reset();
    return;
  }
  try {
    // Read again on every reload: a new password takes effect (and ends every session) with a
    // reload, and a secret file that became readable by others stops the console.
    std::string hash = readConsoleSecret(settings.secret_file);
    const std::chrono::minutes session_length(settings.session_minutes);
    if (console_auth_)
      console_auth_->setPasswordHash(std::move(hash), session_length);
    else
      console_auth_ = std::make_shared<ConsoleAuth>(std::move(hash), session_length);
    if (listener_changed || !console_) {
      console_.reset();
      ConsoleBackend backend{
          [this] { return health(); },
          [] { return logTail(100); },
          [this](KioskAction action) { return requestAction(action); },
          [this] { requestReload(); },
          [this](SnapshotKind kind, int index) { return snapshotJpeg(kind, index); },
      };
      console_ = std::make_unique<ConsoleServer>(settings.address, static_cast<std::uint16_t>(settings.port),
                                                 console_auth_, std::move(backend));
      if (isLoopbackAddress(settings.address))
        HOLO_LOG_INFO("console on http://{}:{}/", settings.address, console_->port());
      else
        HOLO_LOG_WARN("console on the network at http://{}:{}/ (plain HTTP, see docs/security.md)",
                      settings.address, console_->port());
    }
  } catch (const std::exception& e) {
    // Fail closed: no console rather than one with a password others could read.
    console_.reset();
    console_auth_.reset();
    HOLO_LOG_ERROR("console not started: {}", e.what());
    std::lock_guard lock(mutex_);
    health_.addError(std::string("console not started: ") + e.what());
  }
}

std::uint16_t KioskLoop::consolePort() const {
  return console_ ? console_->port() : 0;
}

bool KioskLoop::requestAction(KioskAction action) {
  std::lock_guard lock(actions_mutex_);
  if (pending_actions_.size() >= kMaxPendingActions) return false;
  pending_actions_.push_back(action);
  return true;
}

void KioskLoop::requestReload() {
  reload_requested_ = true;
}

bool KioskLoop::snapshotWanted(Clock::time_point now) {
  const auto until = Clock::time_point(Clock::duration(snapshot_wanted_until_ns_.load()));
  if (now >= until) return false;
  if (now - last_snapshot_ < std::chrono::duration<double>(1.0 / kSnapshotsPerSecond)) return false;
  last_snapshot_ = now;
  return true;
}

std::string KioskLoop::snapshotJpeg(SnapshotKind kind, int index) {
  const auto now = Clock::now();
  const auto until =
      now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kSnapshotInterestS));
  snapshot_wanted_until_ns_ = std::chrono::duration_cast<Clock::duration>(until.time_since_epoch()).count();
  std::shared_ptr<const FrameSnapshot> snapshot;
  std::int64_t sequence = 0;
  {
    std::lock_guard lock(snapshot_mutex_);
    snapshot = snapshot_;
    sequence = snapshot_sequence_;
    const auto cached = jpegs_.find({kind, index});
    if (cached != jpegs_.end() && cached->second.sequence == sequence) return cached->second.bytes;
  }
  if (!snapshot || index < 0) return {};
  const auto i = static_cast<std::size_t>(index);
  cv::Mat picture;
  if (kind == SnapshotKind::Face && i < snapshot->faces.size()) picture = snapshot->faces[i];
  if (kind == SnapshotKind::Camera && i < snapshot->cameras.size()) picture = snapshot->cameras[i];
  if (picture.empty() || picture.depth() != CV_8U) return {};
  constexpr int kMaxWidth = 640;
  if (picture.cols > kMaxWidth)
    cv::resize(picture, picture, {kMaxWidth, std::max(1, picture.rows * kMaxWidth / picture.cols)}, 0, 0,
               cv::INTER_AREA);
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".jpg", picture, bytes, {cv::IMWRITE_JPEG_QUALITY, 80})) return {};
  std::string jpeg(bytes.begin(), bytes.end());
  std::lock_guard lock(snapshot_mutex_);
  jpegs_[{kind, index}] = {sequence, jpeg};
  return jpeg;
}

std::uint16_t KioskLoop::healthPort() const {
  return server_ ? server_->port() : 0;
}

HealthStatus KioskLoop::health() const {
  std::lock_guard lock(mutex_);
  HealthStatus h = health_;
  const auto now = Clock::now();
  h.uptime_s = std::chrono::duration<double>(now - started_).count();
  h.seconds_since_frame =
      last_frame_ ? std::chrono::duration<double>(now - *last_frame_).count() : h.uptime_s;
  return h;
}

void KioskLoop::publish(SystemdNotifier& notifier, bool force) {
  const auto now = Clock::now();
  if (!force && std::chrono::duration<double>(now - last_publish_).count() < config_.kiosk.status_interval_s)
    return;
  last_publish_ = now;
  const HealthStatus h = health();
  if (ready_sent_) notifier.status(h.summary());
  if (!config_.kiosk.health_file.empty()) {
    try {
      writeFileAtomically(config_.kiosk.health_file, h.toJson().dump(2) + "\n");
    } catch (const std::exception& e) {
      // Once: a read-only folder would otherwise flood the journal every status interval.
      if (!health_file_warned_) HOLO_LOG_WARN("health file not written: {}", e.what());
      health_file_warned_ = true;
      stats::add("Kiosk/Health file write failures");
    }
  }
}

void KioskLoop::frame(SystemdNotifier& notifier) {
  const bool blank = !config_.kiosk.opening_hours.isOpen(std::chrono::system_clock::now());
  if (blank != was_blank_)
    HOLO_LOG_INFO(blank ? "closing time: blanking the monitors" : "opening: resuming the picture");
  was_blank_ = blank;
  FrameRequest request{index_++, policy_->quality(), policy_->qualityName(), policy_->mode(), blank, {},
                       false};
  {
    std::lock_guard lock(actions_mutex_);
    request.actions.assign(pending_actions_.begin(), pending_actions_.end());
    pending_actions_.clear();
  }
  for (const KioskAction action : request.actions)
    HOLO_LOG_INFO("frame {}: {} handed to the frame source", request.index, kioskActionName(action));

  const auto t0 = Clock::now();
  request.snapshot = snapshotWanted(t0);
  FrameReport report;
  try {
    report = render_(request);
  } catch (const std::exception& e) {
    report.presented = false;
    report.errors.push_back(std::string("frame failed: ") + e.what());
    stats::add("Kiosk/Frames failed");
    // A failed frame says nothing about the cameras: keep the last known states, or a single
    // render error would count as every camera lost and drop the foreground.
    std::lock_guard lock(mutex_);
    report.cameras = health_.cameras;
  }
  const auto t1 = Clock::now();
  const double frame_ms = msBetween(t0, t1);
  if (report.snapshot) {
    auto snapshot = std::make_shared<const FrameSnapshot>(std::move(*report.snapshot));
    std::lock_guard lock(snapshot_mutex_);
    snapshot_ = std::move(snapshot);
    ++snapshot_sequence_;
  }

  int alive = 0;
  for (const auto& c : report.cameras) alive += c.alive ? 1 : 0;
  const int total = static_cast<int>(report.cameras.size());
  DegradationDecision decision{policy_->quality(), policy_->mode(), false, false};
  // Black frames say nothing about the renderer's load, and the first frames after a start or
  // reload compile shaders and fill caches (hundreds of ms): neither may lower the quality.
  if (!blank && warmup_frames_left_ > 0)
    --warmup_frames_left_;
  else if (!blank)
    decision = policy_->update(frame_ms, alive, total);
  if (decision.quality_changed)
    HOLO_LOG_WARN("frame time {:.1f} ms (budget {:.1f} ms): quality now '{}'", frame_ms,
                  config_.kiosk.degradation.frame_budget_ms, policy_->qualityName());
  // Without cameras configured (a stand-in frame source) ibl-only is the plan, not a fault. A
  // further loss while already degraded (a second camera lost a frame after the first) changes
  // no mode but is reported too: the log then reads 3/4, 2/4 whatever order the losses came in.
  const bool further_loss = cameras_alive_last_frame_ >= 0 && alive < cameras_alive_last_frame_ &&
                            decision.mode != RenderMode::Full;
  cameras_alive_last_frame_ = alive;
  const bool mode_fault = (decision.mode_changed || further_loss) && total > 0;
  if (mode_fault) HOLO_LOG_WARN("cameras {}/{}: mode now '{}'", alive, total, renderModeName(decision.mode));

  if (report.presented) {
    watchdog_->frameCompleted(t1);
    ++fps_window_frames_;
  }
  {
    std::lock_guard lock(mutex_);
    if (report.presented) {
      last_frame_ = t1;
      ++health_.frames;
    }
    for (const auto& e : report.errors) {
      stats::add("Kiosk/Frame faults");
      // A fault that repeats every frame is reported once, not 25 times a second.
      if (!health_.last_errors.empty() && health_.last_errors.back() == e) continue;
      HOLO_LOG_WARN("{}", e);
      health_.addError(e);
    }
    if (decision.quality_changed)
      health_.addError("quality stepped to '" + policy_->qualityName() + "' at frame time " +
                       std::to_string(std::lround(frame_ms)) + " ms");
    if (mode_fault)
      health_.addError("mode '" + std::string(renderModeName(decision.mode)) + "' with cameras " +
                       std::to_string(alive) + "/" + std::to_string(total));
    health_.state = blank ? "blanked" : "running";
    health_.mode = renderModeName(policy_->mode());
    health_.quality = policy_->qualityName();
    health_.quality_level = policy_->quality();
    health_.frame_ms = policy_->smoothedFrameMs();
    health_.stage_ms = report.stage_ms;
    health_.stage_ms["frame"] = frame_ms;
    health_.cameras = report.cameras;
    health_.foreground_share = report.foreground_share;
    health_.camera_skew_ms = report.camera_skew_ms;
    health_.relic = report.relic;
    health_.next_relic = report.next_relic;
    health_.exhibit_problems = report.exhibit_problems;
    const double window_s = std::chrono::duration<double>(t1 - fps_window_start_).count();
    if (window_s >= 1.0) {
      health_.fps = static_cast<double>(fps_window_frames_) / window_s;
      fps_window_start_ = t1;
      fps_window_frames_ = 0;
    }
  }
  if (report.presented && !ready_sent_) {
    ready_sent_ = true;
    const HealthStatus h = health();
    HOLO_LOG_INFO("first frame on screen after {:.2f} s: ready", h.uptime_s);
    notifier.ready(h.summary());
    publish(notifier, true);
  }
}

void KioskLoop::reload(SystemdNotifier& notifier) {
  notifier.reloading();
  applyConfig(reload_());
  const HealthStatus h = health();
  notifier.ready(h.summary());
  publish(notifier, true);
}

int KioskLoop::run(SignalEvents& signals, SystemdNotifier& notifier, std::int64_t stop_after_frames) {
  watchdog_ =
      std::make_unique<FrameWatchdog>(notifier.watchdogTimeout(), [&notifier] { notifier.watchdog(); });
  if (const auto interval = watchdog_->petInterval())
    HOLO_LOG_INFO("systemd watchdog: WATCHDOG=1 every {:.3f} s while frames are presented",
                  std::chrono::duration<double>(*interval).count());
  fps_window_start_ = Clock::now();
  for (;;) {
    const auto frame_start = Clock::now();
    frame(notifier);
    publish(notifier, false);
    if (stop_after_frames > 0 && index_ >= stop_after_frames) break;

    // Pace to max_fps (2 fps when blanked); the wait is the signal poll, so signals are handled
    // at once even while idle.
    const double fps = was_blank_ ? kBlankFps : config_.kiosk.max_fps;
    const auto next =
        frame_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps));
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now());
    bool stop = false;
    for (const SignalEvent event : signals.poll(std::max(wait, std::chrono::milliseconds(0)))) {
      if (event == SignalEvent::Stop) {
        stop = true;
      } else {
        HOLO_LOG_INFO("SIGHUP: reloading the configuration");
        reload(notifier);
      }
    }
    if (stop) break;
    if (reload_requested_.exchange(false)) {
      HOLO_LOG_INFO("console: reloading the configuration");
      reload(notifier);
    }
  }
  HOLO_LOG_INFO("stopping");
  notifier.stopping();
  {
    std::lock_guard lock(mutex_);
    health_.state = "stopping";
  }
  publish(notifier, true);
  console_.reset();
  server_.reset();
  return 0;
}

}  // namespace holo::kiosk
