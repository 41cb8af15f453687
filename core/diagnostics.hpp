#pragma once
// What the estimator tells the world besides the estimate itself, as one value (the idea of
// x-io Fusion's GetInternalStates): sinks — DDS, summaries, the state saver — read this and
// never the estimator's internals, so they do not depend on which method is in force.
#include <array>
#include <cstdint>
#include <limits>

#include "core/estimate.hpp"
#include "core/method.hpp"
#include "core/sample.hpp"
#include "core/temperature_model.hpp"

namespace headingd::core {

struct TemperatureModelState {
  bool ready = false;            // the slope is in use
  double slope_dps_per_c = 0.0;  // at 25 degC
  double weighted_span_c = 0.0;  // spread of the points it rests on
  std::uint32_t points = 0;      // accepted segments it has seen
};

struct Diagnostics {
  Method method = Method::Auto;
  bool in_startup = true;
  std::uint64_t samples = 0;
  std::uint64_t accepted_segments = 0;
  std::uint64_t rejected_segments = 0;
  std::uint64_t retracted_segments = 0;     // auto: accepted, then taken back (a creep)
  std::uint64_t bias_recoveries = 0;        // auto: restarts from an unexplained quiet period
  std::uint64_t refused_recoveries = 0;     // auto: quiet periods at a level the bias could not reach
  std::uint64_t refuted_models = 0;         // auto: temperature models (per axis) a quiet run contradicted
  std::uint64_t rate_changed_segments = 0;  // auto: passed the mean test, rejected: the rate changed within
  std::uint64_t recoveries_taken_back = 0;  // auto: a later stop agreed with the level replaced
  std::uint64_t saved_bias_restarts = 0;    // auto: of bias_recoveries, a saved bias the first still segment refused
  std::uint64_t saved_noise_replaced = 0;   // auto: a saved sigma_still the first seconds showed wrong
  std::uint64_t trail_restarts = 0;  // auto: of bias_recoveries, on a line the rejected stops drew against temperature
  double trail_slope_z_dps_per_c = 0.0;  // the last such line's slope on z
  // auto: restarts back to a level a stop had measured, whose heading correction a stop after
  // motion confirmed, and the last such correction (deg; the heading jumped by it).
  std::uint64_t returns_mended = 0;
  double last_return_correction_deg = 0.0;
  // auto: gaps in the samples (a lost FIFO, a chip set up again, a recording's hole) bridged at
  // the rate on either side, and their seconds in all.
  std::uint64_t gaps_bridged = 0;
  double gaps_bridged_s = 0.0;
  double segment_s = 0.0;               // the configured segment length
  Vec3 sigma_still_dps = Vec3::Zero();  // per-sample noise while still; zero until measured
  // Angle random walk per axis; zero where the method does not learn it (the paper's A/B/C).
  Vec3 noise_density_dps_rt_hz = Vec3::Zero();
  double last_still_t_s = std::numeric_limits<double>::quiet_NaN();  // end of the last accepted segment
  std::array<TemperatureModelState, 3> temperature{};
  // Heading fixes (set-heading) so far, and the sum of the jumps they made: heading minus this
  // offset is continuous (what the ROS Imu publishes as yaw).
  std::uint64_t heading_fixes = 0;
  // auto: the vehicle's motion hint in force, and stops it claimed that the gyro contradicted.
  MotionHint motion_hint = MotionHint::None;
  std::uint64_t hint_conflicts = 0;
  double heading_fix_offset_deg = 0.0;
  // The z scale factor learned from heading fixes (measured = true * (1 + s)) and its sigma;
  // NaN sigma: none learned.
  double scale_z = 0.0;
  double scale_z_sigma = std::numeric_limits<double>::quiet_NaN();
  // auto: the factor on the heading variance the filter gathered since the last fix (the
  // sigma's calibration by the run's stops and fixes; 1 when off), and what it rests on.
  double heading_variance_scale = 1.0;
  std::uint64_t sigma_stops_weighed = 0;
  std::uint64_t sigma_fixes_weighed = 0;
};

// What survives a restart (the state file): the bias and what was learned about the sensor.
struct LearnedState {
  Vec3 bias_dps = Vec3::Zero();
  Vec3 bias_sigma_dps = Vec3::Zero();   // 0.01 dps where the method has none
  Vec3 sigma_still_dps = Vec3::Zero();  // zero when unknown
  Vec3 arw_dps_rt_hz = Vec3::Zero();    // zero when unknown
  std::array<TemperatureModel::Sums, 3> temperature_sums{};
  std::array<std::uint32_t, 3> temperature_points{};
  // The heading when saved and its variance (NaN: none kept), and the fix offset then, so the
  // heading and the continuous yaw go on across a restart.
  double heading_deg = std::numeric_limits<double>::quiet_NaN();
  double heading_variance_deg2 = std::numeric_limits<double>::quiet_NaN();
  double heading_fix_offset_deg = 0.0;
  // The z scale factor learned from heading fixes (measured = true * (1 + s)) and its sigma;
  // NaN sigma: none learned.
  double scale_z = 0.0;
  double scale_z_sigma = std::numeric_limits<double>::quiet_NaN();
  // The temperature when saved (as the estimator reads it) and the one the bias was last measured
  // at; NaN: unknown. A restart at another temperature carries the bias across the change, as
  // a temperature step while running would: without them a daemon stopped warm and started cold
  // judged its first stops against the warm bias at the warm bias's sigma and rejected them.
  double temp_c = std::numeric_limits<double>::quiet_NaN();
  double bias_measured_temp_c = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace headingd::core
