// The frames a kiosk::KioskLoop shows (kiosk_loop.hpp's RenderFrame), each presented for real:
//  * the pipeline: the live frame loop (frame_loop.hpp) on an installation, at the view size and
//    camera mode the degradation policy asks for (each quality level below the best renders views
//    1.25x smaller, never under 64 pixels; IblOnly switches the foreground off);
//  * the test pattern: the display module's alignment pattern on the four faces, for checking the
//    supervision itself without the cost of rendering.
// Headless, the presented picture is read back and checked: a black frame during opening hours,
// or a picture while blanked, is reported as an error of the frame (the pipeline: every frame; the
// test pattern: every 30th and every blanked one).
// Injected faults (kiosk/fault_injector.hpp, from the environment) act on the real pipeline:
// `camera_off` switches a simulated camera off, so its capture thread loses it and the frame loop
// drops it as stale, exactly as with a pulled cable; `black` presents black over the frame.
//
// The exhibit's playlist (Installation::playlist, exhibit_config.hpp): the pipeline shows its
// relics in turn, each for its duration_s (kiosk time, while open), turning at its
// turntable_deg_per_s, and KioskAction::NextRelic advances it at once. The next relic's stage
// (its BVH and, unless it shares the hall, its prefiltered IBL: FrameLoop's buildStage) is built
// on a worker while the current one shows; a relic whose time is up stays on until the next one
// is ready, so a switch never stalls a frame for the build (PipelineSourceOptions can make it
// wait instead). The switch itself (the renderer rebuilt for the new relic) is logged with its
// time. Cross-fade: the outgoing relic's last picture, frozen, blends into the incoming relic's
// live frames over the incoming entry's crossfade_s (one relic is rendered, never two). Every
// report names the relic on screen and the next one and carries the entries left out
// (Installation::exhibit_problems). A relic's time and turn run on the steady clock from its
// switch.
// Units: milliseconds in FrameReport::stage_ms, pixels for view sizes, seconds and degrees for the
// playlist. The returned callables are copyable (they share their state) and are called on one
// thread.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "holo/display/display_config.hpp"
#include "holo/kiosk/kiosk_loop.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::pipeline {

// A running pipeline source's playlist, replaceable without restarting it (a reload that changes
// only exhibit.relics keeps the frame loop and its picture). The source takes a replacement at its
// next frame: the relic on screen stays, with its new entry's settings, when the new playlist
// names it, and the playlist goes on after it; else the new playlist's first relic fades in.
class ExhibitControl {
 public:
  void replace(std::vector<ExhibitRelic> playlist, std::vector<std::string> problems) {
    pending_ = Replacement{std::move(playlist), std::move(problems)};
  }
  struct Replacement {
    std::vector<ExhibitRelic> playlist;
    std::vector<std::string> problems;
  };
  std::optional<Replacement> take() {
    std::optional<Replacement> taken = std::move(pending_);
    pending_.reset();
    return taken;
  }

 private:
  std::optional<Replacement> pending_;
};

struct PipelineSourceOptions {
  // A relic whose time is up (or a NextRelic) waits for the next relic's stage to be built, so the
  // switch happens on that frame (tests, reproducible runs); else the current relic stays until it
  // is ready.
  bool wait_for_next_relic = false;
  std::shared_ptr<ExhibitControl> control;  // optional: reloads replace the playlist through it
};

// The live frame loop on `installation`, at `view_size` pixels per face at full quality
// (kViewSizeFromScreen, frame_loop.hpp: the size the screen shows a face at).
// Throws InputError when the installation cannot be opened (as FrameLoop does).
kiosk::RenderFrame pipelineFrameSource(const display::DisplayConfig& config, bool headless,
                                       Installation installation, int view_size,
                                       PipelineSourceOptions options = {});

// The four faces' alignment pattern, 320 pixels a side at full quality.
kiosk::RenderFrame testPatternFrameSource(const display::DisplayConfig& config, bool headless);

}  // namespace holo::pipeline
