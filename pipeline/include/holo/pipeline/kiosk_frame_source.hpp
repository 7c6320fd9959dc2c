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
// Units: milliseconds in FrameReport::stage_ms, pixels for view sizes. The returned callables are
// copyable (they share their state) and are called on one thread.
#pragma once

#include "holo/display/display_config.hpp"
#include "holo/kiosk/kiosk_loop.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::pipeline {

// The live frame loop on `installation`, at `view_size` pixels per face at full quality.
// Throws InputError when the installation cannot be opened (as FrameLoop does).
kiosk::RenderFrame pipelineFrameSource(const display::DisplayConfig& config, bool headless,
                                       Installation installation, int view_size);

// The four faces' alignment pattern, 320 pixels a side at full quality.
kiosk::RenderFrame testPatternFrameSource(const display::DisplayConfig& config, bool headless);

}  // namespace holo::pipeline
