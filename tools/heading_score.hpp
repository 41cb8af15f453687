#pragma once
// Scores an estimates CSV against a simulator truth CSV with the paper's metrics.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/heading_metrics.hpp"

namespace headingd::app {

struct TimeSeries {
  std::vector<double> t_s;
  std::vector<double> value;
};

// Reads two named columns of a CSV with '#' comments and a header line.
// Throws drivers::InputError naming file and line.
TimeSeries read_columns(const std::string& path, const std::string& time_column, const std::string& value_column);

// Heading error truth - estimate at each truth instant inside the estimate's span, the
// estimate interpolated linearly in time. `errors`, when given, receives (t_s, error_deg).
core::HeadingMetrics score_heading(const TimeSeries& estimate, const TimeSeries& truth,
                                   std::vector<std::pair<double, double>>* errors = nullptr);

}  // namespace headingd::app
