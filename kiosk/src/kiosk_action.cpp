#include "holo/kiosk/kiosk_action.hpp"

namespace holo::kiosk {

std::string kioskActionName(KioskAction action) {
  switch (action) {
    case KioskAction::NextRelic:
      return "next-relic";
    case KioskAction::RelearnBackground:
      return "relearn-background";
  }
  return "unknown";
}

}  // namespace holo::kiosk
