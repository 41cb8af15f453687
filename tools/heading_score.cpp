#include "tools/heading_score.hpp"

#include <optional>
#include <utility>

#include "io/input_error.hpp"
#include "io/line_reader.hpp"
#include "io/text_fields.hpp"

namespace headingd::app {

TimeSeries read_columns(const std::string& path, const std::string& time_column, const std::string& value_column) {
  // The same discipline as the recording reader: bounded lines, BOM skipped, a truncated last
  // line, a duplicated column or time going backwards are errors naming file and line.
  drivers::LineReader lines(path);
  TimeSeries series;
  std::string_view line;
  std::optional<std::size_t> time_index;
  std::optional<std::size_t> value_index;
  std::size_t columns = 0;
  drivers::Fields fields;
  while (lines.next(line)) {
    const auto text = drivers::trim(line);
    if (text.empty() || text.front() == '#') continue;
    drivers::split_fields(text, ',', fields);
    if (fields.overflow) lines.fail("more than " + std::to_string(drivers::Fields::kMax) + " fields");
    if (!time_index) {
      columns = fields.count;
      for (std::size_t i = 0; i < fields.count; ++i) {
        const auto name = drivers::trim(fields.items[i]);
        for (auto [wanted, index] : {std::pair{&time_column, &time_index}, std::pair{&value_column, &value_index}}) {
          if (name != *wanted) continue;
          if (*index)
            lines.fail("column '" + *wanted + "' appears twice in the header (columns " + std::to_string(**index + 1) +
                       " and " + std::to_string(i + 1) + ")");
          *index = i;
        }
      }
      if (!time_index || !value_index)
        lines.fail("header lacks '" + time_column + "' or '" + value_column +
                   "' (found: " + drivers::printable(text, 200) + ")");
      continue;
    }
    if (fields.count != columns)
      lines.fail("expected " + std::to_string(columns) + " fields, found " + std::to_string(fields.count));
    const auto t = drivers::parse_double(fields.items[*time_index]);
    const auto v = drivers::parse_double(fields.items[*value_index]);
    if (!t || !v) lines.fail("time or value is not a finite number: '" + drivers::printable(text, 80) + "'");
    if (!series.t_s.empty() && !(*t > series.t_s.back())) lines.fail("time does not advance");
    series.t_s.push_back(*t);
    series.value.push_back(*v);
  }
  if (!time_index) lines.fail("no header line");
  return series;
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
