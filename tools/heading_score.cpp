#include "tools/heading_score.hpp"

#include <optional>
#include <utility>

#include "io/input_error.hpp"
#include "io/line_reader.hpp"
#include "io/text_fields.hpp"
#include "tools/csv_table.hpp"

namespace headingd::app {

TimeSeries read_columns(const std::string& path, const std::string& time_column, const std::string& value_column) {
  auto columns = read_table(path, {time_column, value_column});
  return TimeSeries{std::move(columns[0]), std::move(columns[1])};
}

core::HeadingMetrics score_heading(const TimeSeries& estimate, const TimeSeries& truth,
                                   std::vector<std::pair<double, double>>* errors) {
  core::HeadingMetrics metrics;
  if (estimate.t_s.empty()) return metrics;
  std::size_t j = 0;
  constexpr double kEpsilonS = 1e-6;
  for (std::size_t i = 0; i < truth.t_s.size(); ++i) {
    const double t = truth.t_s[i];
    if (t < estimate.t_s.front() - kEpsilonS || t > estimate.t_s.back() + kEpsilonS) continue;
    while (j + 1 < estimate.t_s.size() && estimate.t_s[j + 1] <= t) ++j;
    double heading = estimate.value[j];
    if (j + 1 < estimate.t_s.size() && t > estimate.t_s[j]) {
      const double w = (t - estimate.t_s[j]) / (estimate.t_s[j + 1] - estimate.t_s[j]);
      heading += w * (estimate.value[j + 1] - estimate.value[j]);
    }
    const double error = truth.value[i] - heading;
    metrics.add(t, error);
    if (errors) errors->emplace_back(t, error);
  }
  return metrics;
}

}  // namespace headingd::app
