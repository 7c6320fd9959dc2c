// Which addresses the kiosk's HTTP listeners accept (kiosk.health.address, kiosk.console.address).
// "localhost" counts as 127.0.0.1; host names are refused, so a listener never depends on DNS.
#pragma once

#include <string>

namespace holo::kiosk {

// The address a listener binds for `address`: "localhost" becomes 127.0.0.1, anything else is
// returned as given.
std::string bindableAddress(const std::string& address);
// True for 127.0.0.0/8, "localhost" and ::1: the only addresses the health endpoint accepts.
bool isLoopbackAddress(const std::string& address);
// True for a numeric IPv4 or IPv6 address, or "localhost".
bool isIpAddress(const std::string& address);

}  // namespace holo::kiosk
