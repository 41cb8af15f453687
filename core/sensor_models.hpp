#pragma once
// What the auto estimator learns about its sensor and keeps up to date, apart from the filter:
// the per-sample noise while still (sigma_still, the range gate's scale), the white-noise
// density N (angle random walk, the mean test's scale), the vibration level while moving, and
// a bias-versus-temperature model per axis. Configured values always win over learned ones.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/auto_settings.hpp"
#include "core/bias_tracker.hpp"
#include "core/noise_density.hpp"
#include "core/segment_stats.hpp"
#include "core/temperature_model.hpp"

namespace headingd::core {

class SensorModels {
 public:
  SensorModels(const BiasSettings& segments, const AutoSettings& settings);

  // The start-up segment gives the first noise figures.
  void learn_from_startup(const SegmentStats& stats, const BlockMeans& blocks, double duration_s);
  // Every accepted still segment refines the density.
  void learn_from_still(const BlockMeans& blocks);
  // Restored without a start-up segment and nothing configured: samples are taken as white.
  void assume_white_if_unknown(const SegmentStats& stats, double duration_s);
  // A recovery restarts the bias from a quiet run: its noise is the new still noise, and the
  // temperature model, which learned from the wrong level, starts over.
  void relearn_after_recovery(const Vec3& sigma_dps);
  // A model the data contradict starts over on that axis.
  void forget_temperature_model(int axis) {
    temperature_[static_cast<std::size_t>(axis)] = TemperatureModel(settings_.temperature);
  }
  // The noise figures learned so far may come from a start-up that was a turn: a ramp in it
  // reads as noise, dps where a still gyro has hundredths. If they lie far above this quiet
  // segment's, they start over from it; a steady turn's noise is a still gyro's, and stays.
  void restart_noise_if_inflated(const SegmentStats& stats, const BlockMeans& blocks, double duration_s);
  // A still segment's mean at its mean temperature, once its verdict stands.
  // `run_start_t_s`: the start of the still run it belongs to (TemperatureModel::add).
  void add_temperature_point(double mid_t_s, double temp_c, const Vec3& mean_dps, const Vec3& r_dps2,
                             double run_start_t_s);
  // Whether there is a temperature step from `previous_temp_c` to `temp_c` (both read, and
  // different): the bias sigma follows every one, the bias itself only where a model is in use.
  bool follows_temperature(double temp_c, double previous_temp_c) const {
    return std::isfinite(temp_c) && std::isfinite(previous_temp_c) && temp_c != previous_temp_c;
  }
  // The bias change on one axis that its temperature model predicts for that step, with the
  // variance of the model's slope; false while the model is not in use. (Inline: it runs on
  // every sample.)
  bool temperature_shift(int axis, double temp_c, double previous_temp_c, double& shift_dps,
                         double& slope_variance) const {
    const TemperatureModel& model = temperature_[static_cast<std::size_t>(axis)];
    if (!settings_.use_temperature || !model.ready()) return false;
    // The model's own difference, not slope x step: a slope taken at one end of each step
    // ratchets when the temperature toggles between two readings (the fuzzer found a bias of
    // -10000 dps that way under a quadratic fit); the difference returns to where it started.
    shift_dps = model.predict_dps(temp_c) - model.predict_dps(previous_temp_c);
    slope_variance = model.slope_variance();
    return true;
  }
  // Sample-to-sample differences of the z rate: vibration while moving.
  void track_vibration(const Vec3& rate_dps, double dt_s) {
    Vibration v = vibration();
    step(v, rate_dps.z(), dt_s);
    set_vibration(v);
  }
  // The same on plain values, for a loop that keeps them in registers (AutoEstimator::advance).
  struct Vibration {
    double previous_rate_z_dps, diff_var_z, per_tau;
  };
  Vibration vibration() const { return {previous_rate_z_dps_, diff_var_z_, per_vibration_tau_}; }
  void set_vibration(const Vibration& v) {
    previous_rate_z_dps_ = v.previous_rate_z_dps;
    diff_var_z_ = v.diff_var_z;
  }
  static void step(Vibration& v, double rate_z_dps, double dt_s) {
    const double diff = rate_z_dps - v.previous_rate_z_dps;
    v.previous_rate_z_dps = rate_z_dps;
    const double weight = std::min(1.0, dt_s * v.per_tau);
    v.diff_var_z += weight * (diff * diff - v.diff_var_z);
  }
  // The z process noise at a vibration level (process_white_dps2_s on plain values).
  double white_z_dps2_s(const Vibration& v, double dt_s) const {
    return std::max(white_dps2_s_[2], 0.5 * v.diff_var_z * dt_s);
  }
  // The white rate noise N^2 (dps^2 s) on `axis` for propagating one sample; on z, the
  // vibration when it exceeds the chip's own noise. Vibration is white at the sample rate:
  // half the variance of sample differences, times dt, is its density squared.
  double process_white_dps2_s(int axis, double dt_s) const {
    return axis == 2 ? white_z_dps2_s(vibration(), dt_s) : white_dps2_s_[axis];
  }

  // A restored sigma_still the first seconds after a restart showed wrong: theirs instead
  // (false where one is configured, which always wins).
  bool replace_sigma_still(const Vec3& sigma_dps);
  // After a restart: the noise figures and the temperature models saved before.
  void restore_noise(const Vec3& sigma_still_dps, const Vec3& arw_dps_rt_hz);
  void restore_temperature_model(int axis, const TemperatureModel::Sums& sums, std::uint32_t points) {
    temperature_[static_cast<std::size_t>(axis)].restore(sums, points);
  }

  const Vec3& sigma_still_dps() const { return sigma_still_dps_; }
  const Vec3& white_dps2_s() const { return white_dps2_s_; }  // N^2 per axis
  Vec3 noise_density_dps_rt_hz() const { return white_dps2_s_.cwiseSqrt(); }
  const TemperatureModel& temperature_model(int axis) const { return temperature_[static_cast<std::size_t>(axis)]; }
  using TemperatureModels = std::array<TemperatureModel, 3>;
  const TemperatureModels& temperature_models() const { return temperature_; }
  // A restart taken back: the models as they were before it, without what the other level taught.
  void restore_temperature_models(const TemperatureModels& models) { temperature_ = models; }
  void slope_shown_across_stops(int axis) { temperature_[static_cast<std::size_t>(axis)].slope_shown_across_stops(); }

 private:
  BiasSettings segments_;
  AutoSettings settings_;
  std::array<TemperatureModel, 3> temperature_;
  NoiseDensity pooled_noise_;
  Vec3 sigma_still_dps_ = Vec3::Zero();
  Vec3 white_dps2_s_ = Vec3::Zero();
  double per_vibration_tau_ = 1.0 / settings_.vibration_tau_s;  // a product per sample, not a quotient
  double diff_var_z_ = 0.0;                                     // running mean of squared z sample differences, dps^2
  double previous_rate_z_dps_ = 0.0;
};

}  // namespace headingd::core
