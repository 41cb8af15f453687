#pragma once
// `headingd plot`: a picture of a replay or run, readable at a glance — heading with its +-2 sigma
// band (and the truth and the error when given), the bias per axis with the temperature, the
// still segments shaded.
#include <optional>
#include <string>
#include <vector>

namespace headingd::app {

struct PlotOptions {
  std::string estimates;                 // estimates CSV from replay or run
  std::optional<std::string> truth;      // truth.csv from simulate (time_s, heading_deg)
  std::optional<std::string> recording;  // the recording, for the temperature
  std::vector<std::string> joined;       // or the recordings a `replay --join` read as one run
  std::string output;                    // .png or .svg
};

int run_plot(const PlotOptions& options);

}  // namespace headingd::app
