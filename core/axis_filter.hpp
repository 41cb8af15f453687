#pragma once
// A two-state Kalman filter per gyro axis: the integrated angle and the bias.
//
//   angle_{k+1} = angle_k + (rate_k - bias_k) * dt     process noise: white rate noise N^2 dt
//   bias_{k+1}  = bias_k  (+ a known input)            process noise: bias random walk q dt
//
// The cross-covariance matters: an angle integrated while the bias was wrong is correlated
// with that bias error, so when a still segment measures the bias, the same update also
// corrects the angle integrated since the last one.
#include <Eigen/Core>

namespace headingd::core {

class AxisFilter {
 public:
  struct State {
    double angle_deg = 0.0;
    double bias_dps = 0.0;
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // [angle deg^2, ...; ..., bias dps^2]
  };

  void reset(double bias_dps, double bias_variance_dps2);
  // The filter's values as plain numbers, for a loop that keeps all three axes' in registers
  // while it propagates a run of samples (AutoEstimator::advance).
  struct Plain {
    double angle_deg, bias_dps, p00, p01, p11;
  };
  Plain plain() const {
    const Eigen::Matrix2d& p = state_.covariance;
    return {state_.angle_deg, state_.bias_dps, p(0, 0), p(0, 1), p(1, 1)};
  }
  void set_plain(const Plain& v) {
    state_.angle_deg = v.angle_deg;
    state_.bias_dps = v.bias_dps;
    state_.covariance << v.p00, v.p01, v.p01, v.p11;
  }
  // Integrates one sample: white_dps2_s = N^2 (N in dps/sqrt(Hz)), walk_dps2_per_s = q.
  // (Inline: it runs three times on every sample.)
  static void propagate(Plain& v, double rate_dps, double dt_s, double white_dps2_s, double walk_dps2_per_s) {
    v.angle_deg += (rate_dps - v.bias_dps) * dt_s;
    // P <- F P F' + Q with F = [1, -dt; 0, 1].
    v.p00 = (v.p00 - 2.0 * dt_s * v.p01) + (dt_s * dt_s * v.p11 + white_dps2_s * dt_s);
    v.p01 = v.p01 - dt_s * v.p11;
    v.p11 += walk_dps2_per_s * dt_s;
  }
  void propagate(double rate_dps, double dt_s, double white_dps2_s, double walk_dps2_per_s) {
    Plain v = plain();
    propagate(v, rate_dps, dt_s, white_dps2_s, walk_dps2_per_s);
    set_plain(v);
  }
  // Lets time pass while the angle is known not to change (a still segment): only the bias
  // may drift.
  void let_bias_drift(double dt_s, double walk_dps2_per_s) { state_.covariance(1, 1) += walk_dps2_per_s * dt_s; }
  // A known change of the bias (temperature model), with its variance and the covariance it
  // adds between the angle and the bias (kept within what the two variances allow).
  void shift_bias(double delta_dps, double variance_dps2, double angle_covariance = 0.0);
  // The mean of a still segment measures the bias with variance r. Returns the innovation.
  double measure_bias(double mean_dps, double r_dps2);
  // An external fix of the angle (heading at a reference point) with variance r.
  void measure_angle(double angle_deg, double r_deg2);
  void set_angle(double angle_deg) { state_.angle_deg = angle_deg; }

  // The estimator's other edits of the state, each named for what it means:
  // a bias known from outside (a restart) with its variance, uncorrelated with the angle;
  void set_bias(double bias_dps, double variance_dps2);
  // an exact heading fix: the angle is known, and so uncorrelated with anything;
  void fix_angle(double angle_deg);
  // the angle saved before a restart, with its variance then, uncorrelated with the bias;
  void restore_angle(double angle_deg, double variance_deg2);
  // an error of the angle alone that the filter does not model (a verdict that may be wrong,
  // the scale factor before a fix): its variance added, uncorrelated with the bias;
  void widen_angle(double variance_deg2) { state_.covariance(0, 0) += variance_deg2; }
  // an accepted segment taken back: the filter is linear, so what the `span_s` since did to the
  // state judged still it would have done to the state judged moving; carries the difference
  // across that span (F = [1, -T; 0, 1]) and returns the angle change; with `weight` below 1,
  // the mixture of the two (mean moved by the weight, covariance of the two-point mixture);
  double carry_difference(const State& as_moving, const State& as_still, double span_s, double weight = 1.0);
  // the bias started again from `from` (a quiet run taken for a stop): the new level with its
  // variance, and the angle's variance grown by what the old bias may have cost it.
  void restart_bias(const State& from, double bias_dps, double bias_variance_dps2, double added_angle_variance_deg2);

  const State& state() const { return state_; }
  void restore(const State& state) { state_ = state; }
  double angle_deg() const { return state_.angle_deg; }
  double bias_dps() const { return state_.bias_dps; }
  double angle_variance() const { return state_.covariance(0, 0); }
  double bias_variance() const { return state_.covariance(1, 1); }
  void set_bias_variance(double variance_dps2) { state_.covariance(1, 1) = variance_dps2; }

 private:
  State state_;
};

// The two-point mixture of `a` (probability 1 - w) and `b` (probability w): the mean moved by
// w, the covariance of the mixture.
AxisFilter::State blend(const AxisFilter::State& a, const AxisFilter::State& b, double w);

}  // namespace headingd::core
