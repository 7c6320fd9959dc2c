#include "holo/depthfilter/hole_reason.hpp"

namespace holo::depthfilter {

const char* holeReasonName(HoleReason reason) {
  switch (reason) {
    case HoleReason::None:
      return "none";
    case HoleReason::TrustedNoColourMatch:
      return "trusted precursor, no neighbour of its colour";
    case HoleReason::TrustedOtherSurface:
      return "trusted precursor, its colour on another surface";
    case HoleReason::MaskEdge:
      return "mask edge";
    case HoleReason::DepthEdge:
      return "depth edge";
    case HoleReason::PushDisagrees:
      return "push: parents disagree";
    case HoleReason::PushOutOfReach:
      return "push: out of reach";
    case HoleReason::PushOtherColour:
      return "push: other colour";
    case HoleReason::BetweenSurfaces:
      return "between two surfaces";
  }
  return "?";
}

}  // namespace holo::depthfilter
