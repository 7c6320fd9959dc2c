// Why the temporal depth filter left a foreground pixel without an output depth (a hole): the
// first of its hole-fill rules (temporal_depth_filter.hpp, docs/depthfilter.md "Holes") that
// declined the fill. `eval depth` counts them over the true visitor pixels to show where the
// coverage goes.
#pragma once

#include <array>
#include <cstdint>

namespace holo::depthfilter {

enum class HoleReason : std::uint8_t {
  None = 0,  // not a hole: an output depth, outside the mask, or a learning frame
  // With a trusted precursor (measured within fill_trust_frames), the colour-guided fill:
  TrustedNoColourMatch,  // no measured neighbour within fill_radius has the hole's colour
  TrustedOtherSurface,   // none of the neighbours of its colour lies on the precursor's surface (or
                         // they span two and fill_on_precursor_surface is off)
  // Without one:
  MaskEdge,         // within edge_radius of the mask's edge: no measured neighbour of its colour on one
                    // surface (or fill_mask_edge off)
  DepthEdge,        // within edge_radius of measurements spanning a depth edge
  PushDisagrees,    // no guided fill, and the push declined: its parents disagree or straddle an edge
  PushOutOfReach,   // no guided fill, and no pulled pair within the pyramid's reach (l_max)
  PushOtherColour,  // no guided fill, and the measured pixels behind the push's fill have another colour
  BetweenSurfaces,  // a fill was found, but the hole lies in a gap between two surfaces
};

inline constexpr std::array<HoleReason, 8> kHoleReasons = {HoleReason::TrustedNoColourMatch,
                                                           HoleReason::TrustedOtherSurface,
                                                           HoleReason::MaskEdge,
                                                           HoleReason::DepthEdge,
                                                           HoleReason::PushDisagrees,
                                                           HoleReason::PushOutOfReach,
                                                           HoleReason::PushOtherColour,
                                                           HoleReason::BetweenSurfaces};

// "trusted: no colour match", ... (for tables and JSON keys).
const char* holeReasonName(HoleReason reason);

}  // namespace holo::depthfilter
