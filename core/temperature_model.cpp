#include "core/temperature_model.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace headingd::core {

TemperatureModel::TemperatureModel(const TemperatureModelSettings& settings) : settings_(settings) {}

void TemperatureModel::add(double t_s, double temp_c, double bias_dps, double measurement_variance,
                           double run_start_t_s) {
  if (!std::isfinite(temp_c) || !std::isfinite(bias_dps)) return;
  if (points_ > 0 && t_s > sums_.last_t_s) {
    const double fade = std::exp2(-(t_s - sums_.last_t_s) / settings_.half_life_s);
    sums_.normal *= fade;
    sums_.rhs *= fade;
    sums_.yy *= fade;
    sums_.weight *= fade;
  }
  sums_.last_t_s = t_s;
  const double dt_c = temp_c - settings_.reference_c;
  const Eigen::Vector3d phi(1.0, dt_c, dt_c * dt_c);
  sums_.normal += phi * phi.transpose();
  sums_.rhs += phi * bias_dps;
  sums_.yy += bias_dps * bias_dps;
  sums_.weight += 1.0;
  ++points_;
  noise_variance_ = points_ == 1
                        ? measurement_variance
                        : noise_variance_ + (measurement_variance - noise_variance_) / std::min<double>(points_, 50.0);
  add_to_run(temp_c, bias_dps, run_start_t_s);
  solve();
}

void TemperatureModel::add_to_run(double temp_c, double bias_dps, double run_start_t_s) {
  if (!(run_start_t_s == run_.start_t_s))
    run_ = Run{.start_t_s = run_start_t_s, .count = 0, .slope = {}};  // NaN never continues
  ++run_.count;
  run_.slope.add(1.0, temp_c, Vec3::Constant(bias_dps));  // every segment counts once, as in the model
  if (run_showed_slope_ || run_.count < settings_.min_points) return;
  LevelSlope::Fit fit;
  if (!run_.slope.fit(Vec3::Constant(noise_variance_), fit)) return;
  // The same spread measure as weighted_span_c (two standard deviations times sqrt(3)).
  if (2.0 * std::sqrt(3.0 * fit.temp_variance_c2) < settings_.early_span_c) return;
  run_showed_slope_ = steep(fit.slope_dps_per_c.x(), fit.slope_variance.x());
}

void TemperatureModel::restore(const Sums& sums, std::uint32_t points) {
  sums_ = sums;
  points_ = points;
  solve();
}

double TemperatureModel::weighted_span_c() const {
  if (sums_.weight <= 0.0) return 0.0;
  const double mean = sums_.normal(0, 1) / sums_.weight;
  const double var = sums_.normal(1, 1) / sums_.weight - mean * mean;
  // Two standard deviations: a uniform spread of width w has sd w / sqrt(12) ~ w / 3.5.
  return var > 0.0 ? 2.0 * std::sqrt(var) * std::sqrt(3.0) : 0.0;
}

void TemperatureModel::solve() {
  ready_ = false;
  coefficients_.setZero();
  slope_variance_ = 0.0;
  const double span_c = weighted_span_c();
  const bool early = span_c < settings_.min_span_c;
  if (points_ < settings_.min_points || (early && !run_showed_slope_)) return;
  const bool quadratic = span_c >= settings_.quadratic_span_c;
  const int n = quadratic ? 3 : 2;
  const Eigen::MatrixXd a = sums_.normal.topLeftCorner(n, n);
  const Eigen::VectorXd b = sums_.rhs.head(n);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return;
  const Eigen::VectorXd c = ldlt.solve(b);
  if (!c.allFinite()) return;
  coefficients_.head(n) = c;
  // Residual variance from the sums: RSS = yy - 2 c'b + c'Ac, per unit weight.
  const double rss = std::max(0.0, sums_.yy - 2.0 * c.dot(b) + c.dot(a * c));
  const double dof = std::max(1.0, sums_.weight - n);
  const double residual_variance = std::max(rss / dof, noise_variance_);
  const Eigen::MatrixXd inverse = ldlt.solve(Eigen::MatrixXd::Identity(n, n));
  slope_variance_ = residual_variance * inverse(1, 1);
  // Early, only while all points together say the same as the run did.
  if (early && !steep(c(1), slope_variance_)) {
    coefficients_.setZero();
    slope_variance_ = 0.0;
    return;
  }
  ready_ = true;
}

double TemperatureModel::slope_dps_per_c(double temp_c) const {
  if (!ready_ || !std::isfinite(temp_c)) return 0.0;
  return coefficients_(1) + 2.0 * coefficients_(2) * (temp_c - settings_.reference_c);
}

double TemperatureModel::predict_dps(double temp_c) const {
  const double dt_c = temp_c - settings_.reference_c;
  return coefficients_(0) + coefficients_(1) * dt_c + coefficients_(2) * dt_c * dt_c;
}

}  // namespace headingd::core
