// libFuzzer target: the TOML configuration parser and its validation.
#include <string_view>

#include "service/config_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  try {
    headingd::app::parse_config(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const headingd::app::ConfigError&) {
  }
  return 0;
}
