#include "core/axis_filter.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {

void AxisFilter::reset(double bias_dps, double bias_variance_dps2) {
  state_ = State{};
  state_.bias_dps = bias_dps;
  state_.covariance(1, 1) = bias_variance_dps2;
}

void AxisFilter::shift_bias(double delta_dps, double variance_dps2, double angle_covariance) {
  Eigen::Matrix2d& p = state_.covariance;
  state_.bias_dps += delta_dps;
  p(1, 1) += variance_dps2;
  if (angle_covariance != 0.0 && std::isfinite(angle_covariance)) {
    const double bound = std::sqrt(std::max(0.0, p(0, 0) * p(1, 1)));
    p(0, 1) = std::clamp(p(0, 1) + angle_covariance, -bound, bound);
    p(1, 0) = p(0, 1);
  }
}

double AxisFilter::measure_bias(double mean_dps, double r_dps2) {
  Eigen::Matrix2d& p = state_.covariance;
  const double innovation = mean_dps - state_.bias_dps;
  const double s = p(1, 1) + r_dps2;
  const Eigen::Vector2d gain(p(0, 1) / s, p(1, 1) / s);
  state_.angle_deg += gain(0) * innovation;
  state_.bias_dps += gain(1) * innovation;
  // Joseph-free form is fine here: the gain is optimal and the state is two-dimensional;
  // symmetrise to keep rounding from breaking positive definiteness over months.
  const Eigen::RowVector2d h_p = p.row(1);
  p -= gain * h_p;
  p = 0.5 * (p + p.transpose()).eval();
  return innovation;
}

void AxisFilter::measure_angle(double angle_deg, double r_deg2) {
  Eigen::Matrix2d& p = state_.covariance;
  const double innovation = angle_deg - state_.angle_deg;
  const double s = p(0, 0) + r_deg2;
  const Eigen::Vector2d gain(p(0, 0) / s, p(1, 0) / s);
  state_.angle_deg += gain(0) * innovation;
  state_.bias_dps += gain(1) * innovation;
  const Eigen::RowVector2d h_p = p.row(0);
  p -= gain * h_p;
  p = 0.5 * (p + p.transpose()).eval();
}

void AxisFilter::set_bias(double bias_dps, double variance_dps2) {
  state_.bias_dps = bias_dps;
  state_.covariance(1, 1) = variance_dps2;
  state_.covariance(0, 1) = state_.covariance(1, 0) = 0.0;
}

void AxisFilter::fix_angle(double angle_deg) {
  state_.angle_deg = angle_deg;
  state_.covariance(0, 0) = 0.0;
  state_.covariance(0, 1) = state_.covariance(1, 0) = 0.0;
}

void AxisFilter::restore_angle(double angle_deg, double variance_deg2) {
  fix_angle(angle_deg);
  state_.covariance(0, 0) = variance_deg2;
}

double AxisFilter::carry_difference(const State& as_moving, const State& as_still, double span_s, double weight) {
  Eigen::Matrix2d f;
  f << 1.0, -span_s, 0.0, 1.0;
  const double full_bias = as_moving.bias_dps - as_still.bias_dps;
  const Eigen::Vector2d full((as_moving.angle_deg - as_still.angle_deg) - span_s * full_bias, full_bias);
  const double d_angle = weight * full(0);
  state_.angle_deg += d_angle;
  state_.bias_dps += weight * full(1);
  // Mixture of "still" (weight 1 - w) and "moving" (w): P + w dP + w (1 - w) d d'.
  state_.covariance += weight * (f * (as_moving.covariance - as_still.covariance) * f.transpose()) +
                       weight * (1.0 - weight) * full * full.transpose();
  state_.covariance = 0.5 * (state_.covariance + state_.covariance.transpose()).eval();
  return d_angle;
}

void AxisFilter::restart_bias(const State& from, double bias_dps, double bias_variance_dps2,
                              double added_angle_variance_deg2) {
  state_ = from;
  state_.bias_dps = bias_dps;
  state_.covariance(0, 0) += added_angle_variance_deg2;
  state_.covariance(0, 1) = state_.covariance(1, 0) = 0.0;
  state_.covariance(1, 1) = bias_variance_dps2;
}

AxisFilter::State blend(const AxisFilter::State& a, const AxisFilter::State& b, double w) {
  const Eigen::Vector2d d(b.angle_deg - a.angle_deg, b.bias_dps - a.bias_dps);
  AxisFilter::State mixed;
  mixed.angle_deg = a.angle_deg + w * d(0);
  mixed.bias_dps = a.bias_dps + w * d(1);
  mixed.covariance = a.covariance + w * (b.covariance - a.covariance) + w * (1.0 - w) * d * d.transpose();
  return mixed;
}

}  // namespace headingd::core
