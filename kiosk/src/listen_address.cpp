#include "holo/kiosk/listen_address.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

namespace holo::kiosk {

std::string bindableAddress(const std::string& address) {
  return address == "localhost" ? "127.0.0.1" : address;
}

bool isLoopbackAddress(const std::string& address) {
  const std::string name = bindableAddress(address);
  in_addr v4{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, name.c_str(), &v6) == 1) return IN6_IS_ADDR_LOOPBACK(&v6);
  return false;
}

bool isIpAddress(const std::string& address) {
  const std::string name = bindableAddress(address);
  in_addr v4{};
  in6_addr v6{};
  return inet_pton(AF_INET, name.c_str(), &v4) == 1 || inet_pton(AF_INET6, name.c_str(), &v6) == 1;
}

}  // namespace holo::kiosk
