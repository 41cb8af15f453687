#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace headingd::app {

// A Discovery Server's address as Fast DDS needs it: a numeric IPv4 address (Fast DDS does not
// resolve names here and would silently use 0.0.0.0) and a UDP port.
struct ServerAddress {
  std::string ipv4;
  std::uint16_t port = 0;
};

// Parses "A.B.C.D:PORT" with PORT in [1, 65535]; on failure returns nothing and says why in `why`.
std::optional<ServerAddress> parse_server_address(const std::string& text, std::string& why);

}  // namespace headingd::app
