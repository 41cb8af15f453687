#pragma once
#include <optional>
#include <string>

namespace headingd::app {

struct ReplayOptions {
  std::string input;
  std::optional<std::string> method;  // auto, a, b or c; overrides the config file
  std::string output = "-";           // estimates CSV; "-" is standard output
  double output_rate_hz = 10.0;       // 0: every sample
  std::optional<std::string> config_path;
  bool quiet = false;                 // no summary on stderr
};

// Replays a recording through the estimator; returns the process exit code. Errors and the
// summary go to stderr. On bad input the estimates up to the bad line are kept.
int run_replay(const ReplayOptions& options);

}  // namespace headingd::app
