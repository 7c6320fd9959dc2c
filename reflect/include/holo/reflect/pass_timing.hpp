// The wall time of one frame-renderer pass (effect_plan.hpp's Pass), as a frame's statistics
// list them.
#pragma once

#include "holo/reflect/effect_plan.hpp"

namespace holo::reflect {

struct PassTiming {
  Pass pass;
  double ms = 0.0;  // milliseconds of wall time
};

}  // namespace holo::reflect
