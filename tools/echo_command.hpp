#pragma once
#include <optional>
#include <string>
#include <vector>

namespace headingd::app {

struct EchoOptions {
  std::vector<std::string> topics;  // orientation, imu, bias, status, command; empty = the first four
  bool json = false;
  std::uint64_t count = 0;  // stop after this many messages (0: never)
  double timeout_s = 0.0;   // stop after this long (0: never)
  bool reliable = false;    // ask for reliable orientation/imu (needs a reliable writer)
  std::optional<std::string> config_path;
};

// Subscribes and prints one line per message. Returns the exit code.
int run_echo(const EchoOptions& options);

struct CommandOptions {
  std::string kind;  // set-heading, stopped, moving, clear
  double heading_deg = 0.0;
  double variance_deg2 = 0.0;
  std::optional<double> heading_rad;  // raw value as sent (tests: NaN and friends)
  double stamp_offset_s = 0.0;        // shift the stamp (tests: stale commands)
  std::optional<std::string> config_path;
  double wait_s = 3.0;  // wait this long for the daemon to match before sending
};

// Publishes one HeadingCommand. Returns the exit code.
int run_command(const CommandOptions& options);

}  // namespace headingd::app
