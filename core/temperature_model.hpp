#pragma once
// Bias against temperature, learned online from accepted still segments (Android's sensor
// hub does the same): weighted least squares of bias = c0 + c1 dT (+ c2 dT^2), dT = T - T_ref,
// with exponential ageing so that old points fade (the chip's trim and mounting stress move).
// One model per axis; the estimator uses its slope to carry the bias across temperature
// changes while the platform drives.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/level_slope.hpp"

namespace headingd::core {

struct TemperatureModelSettings {
  double reference_c = 25.0;        // T_ref, degC: keeps the normal equations well conditioned
  double half_life_s = 6 * 3600.0;  // a point's weight halves in this time, s
  double min_span_c = 2.0;          // weighted temperature spread needed before the slope is used, degC
  double quadratic_span_c = 15.0;   // spread above which the quadratic term is fitted, degC
  std::uint32_t min_points = 8;     // accepted segments needed before the slope is used
  // Sooner, where one still run (accepted segments back to back: one stop, no motion between)
  // of min_points or more, spread over early_span_c, shows on its own a slope its fit is sure
  // of (early_sigmas of its sigma from zero) and steeper than early_slope_dps_per_c, which the
  // estimator sets to 3x the drift it assumes without a model: a drift the bias filter does
  // not follow between segments. The L3GD20H datasheet's typical +-0.04 dps/C through a
  // warm-up had four in ten of a parked hour's segments rejected, and the restarts that
  // followed threw the model away, before the spread reached min_span_c
  // (bench/datasheet_tempco.sh). One run, because a steep slope over a fraction of a degree
  // across stops is as often a creep taken for still as the temperature's doing.
  double early_span_c = 0.25;
  double early_sigmas = 3.0;
  double early_slope_dps_per_c = 0.009;
};

inline constexpr TemperatureModelSettings kDefaultTemperatureModelSettings{};

class TemperatureModel {
 public:
  explicit TemperatureModel(const TemperatureModelSettings& settings = kDefaultTemperatureModelSettings);

  // One accepted segment: its mean bias (dps) at its mean temperature (degC), at time t_s.
  // measurement_variance is that mean's variance (dps^2). `run_start_t_s`: the start of the
  // still run the segment belongs to (points with the same start are one run; NaN: none).
  void add(double t_s, double temp_c, double bias_dps, double measurement_variance,
           double run_start_t_s = std::numeric_limits<double>::quiet_NaN());

  bool ready() const { return ready_; }
  // Whether a still run has shown a slope steep enough to use the model before min_span_c.
  bool run_showed_slope() const { return run_showed_slope_; }
  // Stops the estimator rejected have shown such a slope across them (TemperatureTrail): as one
  // run's would, it lets the model be used before min_span_c while all its points agree.
  void slope_shown_across_stops() {
    run_showed_slope_ = true;
    solve();
  }
  // d bias / d T at temp_c (dps per degC) and its variance; zero slope while not ready.
  double slope_dps_per_c(double temp_c) const;
  double slope_variance() const { return slope_variance_; }
  double predict_dps(double temp_c) const;  // bias at temp_c (valid only when ready)
  Eigen::Vector3d coefficients() const { return coefficients_; }
  double weighted_span_c() const;
  std::uint32_t points() const { return points_; }

  // For persistence: the ageing sums themselves.
  struct Sums {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();  // sum w phi phi'
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();     // sum w phi y
    double yy = 0.0;                                   // sum w y^2
    double weight = 0.0;                               // sum w
    double last_t_s = 0.0;
  };
  const Sums& sums() const { return sums_; }
  void restore(const Sums& sums, std::uint32_t points);

 private:
  void solve();
  void add_to_run(double temp_c, double bias_dps, double run_start_t_s);
  bool steep(double slope, double variance) const {
    return std::abs(slope) > settings_.early_slope_dps_per_c &&
           slope * slope > settings_.early_sigmas * settings_.early_sigmas * variance;
  }

  // The current still run's own regression (not aged: a run lasts minutes to hours). LevelSlope
  // fits three axes; this model is one axis, so its level rides on every axis and x is read.
  struct Run {
    double start_t_s = std::numeric_limits<double>::quiet_NaN();
    std::uint32_t count = 0;
    LevelSlope slope;
  };

  TemperatureModelSettings settings_;
  Sums sums_;
  std::uint32_t points_ = 0;
  bool ready_ = false;
  Eigen::Vector3d coefficients_ = Eigen::Vector3d::Zero();
  double slope_variance_ = 0.0;
  double noise_variance_ = 0.0;  // typical measurement variance, weighted
  Run run_;
  bool run_showed_slope_ = false;  // not saved: a restart waits for min_span_c or another run
};

}  // namespace headingd::core
