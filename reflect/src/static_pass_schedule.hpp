// Which views trace their static passes again this frame (internal, for frame_renderer.cpp).
//
// A view whose eye moved beyond TracerSettings::static_reuse_distance traces its hit points and
// static shading again, which costs several times its foreground walk: when two or three views'
// eyes move in the same frame, that frame takes twice the others' time (a stutter). With a budget
// of static_retraces_per_frame, only that many of those views trace in one frame; the others
// show their cached passes one frame more (deferred), as long as their eye is within
// static_defer_distance of the one they were traced from. A view that cannot show its cache (none
// yet, another size, lit anew, its eye beyond the defer distance) always traces and takes from
// the budget first. Among the views that may wait, the one that has waited the most frames
// traces first, then the one whose eye moved farthest, then the lowest index: no view waits more
// frames than there are views.
#pragma once

#include <cstdint>
#include <vector>

namespace holo::reflect {

enum class StaticPass : std::uint8_t {
  Reuse,  // the eye within static_reuse_distance: the cache is this view's picture
  Trace,  // traced again this frame
  Defer,  // due a trace, shown from its cache this frame
};

struct ViewReuseState {
  bool cache_shown = false;   // the cache can be shown: traced, same size, not lit anew
  bool within_reuse = false;  // the eye within static_reuse_distance of the cache's
  bool within_defer = false;  // within static_defer_distance
  float moved = 0.0f;         // metres between the eye and the cache's
  int waited = 0;             // frames this view has been deferred in a row
};

// retraces_per_frame 0: no budget, every view due a trace traces.
std::vector<StaticPass> scheduleStaticPasses(const std::vector<ViewReuseState>& views,
                                             int retraces_per_frame);

}  // namespace holo::reflect
