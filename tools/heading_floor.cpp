#include "tools/heading_floor.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include "io/csv_replay.hpp"
#include "tools/csv_table.hpp"

namespace headingd::app {
namespace {

// Linear interpolation of `values` at `t`, from index `k` (t_s[k] <= t), held at the ends.
double at(const std::vector<double>& t_s, const std::vector<double>& values, std::size_t k, double t) {
  if (k + 1 >= t_s.size() || t <= t_s[k]) return values[k];
  const double w = (t - t_s[k]) / (t_s[k + 1] - t_s[k]);
  return values[k] + w * (values[k + 1] - values[k]);
}

}  // namespace

Truth read_truth(const std::string& path) {
  auto columns = read_table(path, {"time_s", "heading_deg", "bias_z_dps", "moving"});
  Truth truth;
  truth.heading = TimeSeries{std::move(columns[0]), std::move(columns[1])};
  truth.bias_z_dps = std::move(columns[2]);
  truth.moving = std::move(columns[3]);
  return truth;
}

TimeSeries floor_heading(const std::string& recording, const Truth& truth) {
  TimeSeries floor;
  const std::vector<double>& truth_t = truth.heading.t_s;
  if (truth_t.empty()) return floor;
  drivers::CsvReplaySource source(recording);
  std::vector<core::Sample> batch(4096);
  std::size_t k = 0;  // truth row at or before the sample
  double heading = std::nan("");
  double previous_t = 0.0;
  while (const std::size_t count = source.read(batch)) {
    for (std::size_t i = 0; i < count; ++i) {
      const core::Sample& s = batch[i];
      if (s.t_s < truth_t.front()) continue;
      const std::size_t before = k;
      while (k + 1 < truth_t.size() && truth_t[k + 1] <= s.t_s) ++k;
      if (std::isnan(heading)) {
        heading = at(truth_t, truth.heading.value, k, s.t_s);
        floor.t_s.push_back(s.t_s);
        floor.value.push_back(heading);
      } else {
        // As the estimator integrates: the sample's rate over the interval that ends at it.
        // Moving at either truth row around the sample: the flag is sampled at 10 Hz and a turn
        // may start or end between rows; integrating a still stretch of a tenth of a second
        // adds only its white noise, leaving out a turn's first tenth would add its angle.
        const bool next_moving = k + 1 < truth.moving.size() && truth.moving[k + 1] != 0.0;
        if (truth.moving[k] != 0.0 || next_moving)
          heading += (s.rate_dps.z() - at(truth_t, truth.bias_z_dps, k, s.t_s)) * (s.t_s - previous_t);
        if (k != before) {  // a truth instant passed: one point per truth interval
          floor.t_s.push_back(s.t_s);
          floor.value.push_back(heading);
        }
      }
      previous_t = s.t_s;
    }
  }
  return floor;
}

}  // namespace headingd::app
