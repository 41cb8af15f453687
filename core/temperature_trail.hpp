#pragma once
// The stops a drifting bias had rejected, read as a line against temperature. Driving through a
// warm-up at the L3GD20H datasheet's typical +-0.04 dps/C (Table 3, OffDr), the bias moves
// 0.01 dps over a 50 s drive where the drift assumed without a temperature model allows a
// tenth of that: every stop after the first drive is rejected, the temperature model gets no
// point to learn from, and no stop lasts the wait a restart needs (bench/datasheet_tempco.sh).
// Each such stop's level still measures the bias. When the last few of them lie on one line
// against their temperatures whose slope is steep and sure, the temperature's doing explains
// them; a run of creeps would have to grow in step with the temperature to look alike. Fitted
// without the level the filter last held (after a drive that lags the stop it accepted: agv at
// 0.04 dps/C, 0.012 dps behind, six of its sigmas); the estimator then asks the line to meet that
// level within such a lag (AutoEstimator::line_meets_measured_level).
#include <array>
#include <cstddef>
#include <optional>

#include "core/sample.hpp"

namespace headingd::core {

struct TemperatureTrailSettings {
  double floor_dps = 0.002;            // what a line misses per stop: curvature, the bias walk between stops
  double sigmas = 3.0;                 // every stop within this many sigmas of the line; the slope this sure
  double min_slope_dps_per_c = 0.009;  // a slope the drift assumed without a model does not explain
  double max_slope_dps_per_c = 0.1;    // beyond the datasheet's figure by far: no zero-rate level's
  // Four stops over half a degree or more: with three, creeps of up to 0.05 dps at random drew
  // a line twice as often (8 % against 3.5 % of 2000 trails in a standalone run of this fit, as
  // tests/test_temperature_trail.cpp sets them up); over a degree, 0.3 %, but found one stop
  // later, the agv worlds at 0.03-0.04 dps/C lost 3-8 deg more first.
  double min_span_c = 0.5;
  std::size_t min_stops = 4;
};

class TemperatureTrail {
 public:
  struct Stop {
    Vec3 level_dps = Vec3::Zero();
    double temp_c = 0.0;
    double duration_s = 0.0;
  };
  static constexpr std::size_t kCapacity = 6;

  explicit TemperatureTrail(const TemperatureTrailSettings& settings = TemperatureTrailSettings{})
      : settings_(settings) {}

  void add(const Stop& stop);  // the oldest goes beyond kCapacity; non-finite stops are ignored
  void clear() { count_ = 0; }
  std::size_t size() const { return count_; }
  const Stop& recent(std::size_t i) const;  // 0: the latest

  struct Line {
    Vec3 slope_dps_per_c = Vec3::Zero();
    Vec3 slope_variance = Vec3::Zero();
    Vec3 level_dps = Vec3::Zero();  // at mean_temp_c (each axis weighs its stops its own way)
    Vec3 level_variance = Vec3::Zero();
    Vec3 mean_temp_c = Vec3::Zero();
    double coldest_c = 0.0, warmest_c = 0.0;  // the stops' temperatures
    std::size_t stops = 0;                    // how many of the latest stops (with `current`) it rests on
    Vec3 at(double temp_c) const {
      return level_dps + slope_dps_per_c.cwiseProduct(Vec3::Constant(temp_c) - mean_temp_c);
    }
    Vec3 variance_at(double temp_c) const {
      return level_variance + slope_variance.cwiseProduct((Vec3::Constant(temp_c) - mean_temp_c).cwiseAbs2());
    }
  };
  // The line through the latest stops ending with `current` (the stop under way), tried on the
  // most stops first. Every axis must fit it; at least one must be steep. `white_dps2_s`: N^2;
  // `reading_variance_c2`: each temperature's own error (TemperatureReading::variance_c2).
  std::optional<Line> explain(const Stop& current, const Vec3& white_dps2_s, double reading_variance_c2) const;

 private:
  std::optional<Line> fit(std::size_t stops, const Stop& current, const Vec3& white_dps2_s,
                          double reading_variance_c2) const;

  TemperatureTrailSettings settings_;
  std::array<Stop, kCapacity> stops_{};
  std::size_t next_ = 0, count_ = 0;
};

}  // namespace headingd::core
