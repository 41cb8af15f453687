#include "dds/server_address.hpp"

#include <arpa/inet.h>

#include <charconv>

namespace headingd::app {

std::optional<ServerAddress> parse_server_address(const std::string& text, std::string& why) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) {
    why = "must be IPV4:PORT, e.g. 127.0.0.1:11811";
    return std::nullopt;
  }
  ServerAddress address;
  address.ipv4 = text.substr(0, colon);
  in_addr parsed{};
  if (inet_pton(AF_INET, address.ipv4.c_str(), &parsed) != 1) {
    why = "'" + address.ipv4 + "' is not a numeric IPv4 address (host names are not resolved here)";
    return std::nullopt;
  }
  const char* first = text.data() + colon + 1;
  const char* last = text.data() + text.size();
  unsigned long port = 0;
  const auto [end, error] = std::from_chars(first, last, port);
  if (first == last || error != std::errc{} || end != last || port < 1 || port > 65535) {
    why = "port '" + std::string(first, last) + "' is not a number in [1, 65535]";
    return std::nullopt;
  }
  address.port = static_cast<std::uint16_t>(port);
  return address;
}

}  // namespace headingd::app
