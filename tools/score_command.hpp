#pragma once
#include <optional>
#include <string>

namespace headingd::app {

struct ScoreOptions {
  std::string estimates;
  std::string truth;
  std::string label;
  std::optional<std::string> errors_output;  // time_h,error_deg at 1 Hz, for plots
  bool header = false;                       // print the table header first
  // The recording the estimates came from: also the floor (tools/heading_floor; the truth must
  // carry bias_z_dps and moving) and the estimate's excess over it.
  std::optional<std::string> recording;
};

// Prints one table row: label, max |E|, final |E|, RMS (deg) and drift (deg/h); with a
// recording two more: "LABEL floor" (the floor against the truth) and "LABEL excess" (the
// estimate less the floor).
int run_score(const ScoreOptions& options);

}  // namespace headingd::app
