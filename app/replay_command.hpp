#pragma once
#include <optional>
#include <string>
#include <vector>

namespace headingd::app {

struct ReplayOptions {
  std::string input;
  // With more than one: replayed one after another as one run (`--join`); `input` unused.
  std::vector<std::string> joined;
  std::optional<std::string> method;  // auto, a, b or c; overrides the config file
  std::string output = "-";           // estimates CSV; "-" is standard output
  double output_rate_hz = 10.0;       // 0: every sample
  std::optional<std::string> config_path;
  bool quiet = false;               // no summary on stderr
  bool publish = false;             // publish over DDS as the daemon does (CLI default: on)
  std::string speed = "max";        // max, realtime, or a factor of real time
  double wait_subscribers_s = 0.0;  // before starting, wait this long for an orientation subscriber
  double linger_s = 0.0;            // after the end, stay this long so late joiners get the latest
};

// Replays a recording through the estimator; returns the process exit code. Errors and the
// summary go to stderr. On bad input the estimates up to the bad line are kept.
int run_replay(const ReplayOptions& options);

}  // namespace headingd::app
