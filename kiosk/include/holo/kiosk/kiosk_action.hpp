// What a technician can ask the running kiosk to do besides reloading its configuration (the web
// console's buttons). KioskLoop carries each request to the frame source once, in the order
// asked, in FrameRequest::actions; the frame source acts on it before rendering that frame.
#pragma once

#include <string>

namespace holo::kiosk {

enum class KioskAction {
  NextRelic,          // show the exhibit playlist's next relic now (its cross-fade starts)
  RelearnBackground,  // forget every camera's background and learn it again from the next frames
};

// "next-relic", "relearn-background": the names the console and the logs use.
std::string kioskActionName(KioskAction action);

}  // namespace holo::kiosk
