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
};

// Prints one table row: label, max |E|, final |E|, RMS (deg) and drift (deg/h).
int run_score(const ScoreOptions& options);

}  // namespace headingd::app
