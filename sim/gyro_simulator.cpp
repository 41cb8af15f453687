#include "sim/gyro_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace headingd::drivers {
namespace {

// Each Gauss-Markov term's Allan deviation peaks near 0.62 of its sigma; three terms a
// decade apart overlap into a floor near 0.664 * bias instability with this share each.
constexpr double kMarkovSigmaPerInstability = 0.55;
constexpr double kSlowUpdateHz = 10.0;  // bias instability and temperature move slowly

double quantise(double value, double quantum, double full_scale) {
  const double clipped = std::clamp(value, -full_scale, full_scale);
  return std::round(clipped / quantum) * quantum;
}

}  // namespace

GyroSimulator::GyroSimulator(Scenario scenario, std::uint64_t seed)
    : scenario_(std::move(scenario)), rng_(seed ^ 0x9e3779b97f4a7c15ULL) {
  const NoiseModel& noise = scenario_.noise;
  // Discrete white noise of per-sample sigma N*sqrt(fs) has Allan deviation N/sqrt(tau);
  // the first-order low-pass keeps that (unit DC gain) while lowering the per-sample sigma.
  white_sigma_dps_ = noise.arw_dps_rt_hz * std::sqrt(noise.rate_hz);
  lpf_alpha_ = std::exp(-2.0 * std::numbers::pi * noise.lpf_hz / noise.rate_hz);
  slow_update_every_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(noise.rate_hz / kSlowUpdateHz));
  for (auto& term : markov_dps_) {
    for (int axis = 0; axis < 3; ++axis)
      term[axis] = kMarkovSigmaPerInstability * noise.bias_instability_dps[axis] * normal_(rng_);
  }
  update_slow_bias(0.0);
  // Start the low-pass in its steady state so the first samples are not artificially quiet.
  const double steady = std::sqrt((1.0 - lpf_alpha_) / (1.0 + lpf_alpha_));
  for (int axis = 0; axis < 3; ++axis) filtered_noise_dps_[axis] = white_sigma_dps_[axis] * steady * normal_(rng_);
}

void GyroSimulator::update_slow_bias(double dt_s) {
  const NoiseModel& noise = scenario_.noise;
  slow_bias_dps_.setZero();
  for (int term = 0; term < kMarkovTerms; ++term) {
    const double phi = std::exp(-dt_s / markov_tau_s_[static_cast<std::size_t>(term)]);
    const double drive = std::sqrt(1.0 - phi * phi);
    auto& state = markov_dps_[static_cast<std::size_t>(term)];
    for (int axis = 0; axis < 3; ++axis) {
      const double sigma = kMarkovSigmaPerInstability * noise.bias_instability_dps[axis];
      state[axis] = phi * state[axis] + sigma * drive * normal_(rng_);
    }
    slow_bias_dps_ += state;
  }
  // Only when configured: the named scenarios keep their random streams, and so their results.
  if (!noise.rate_random_walk_dps_rt_s.isZero()) {
    for (int axis = 0; axis < 3; ++axis)
      walk_bias_dps_[axis] += noise.rate_random_walk_dps_rt_s[axis] * std::sqrt(dt_s) * normal_(rng_);
    slow_bias_dps_ += walk_bias_dps_;
  }
}

double GyroSimulator::knot_offset_c(double t_s) {
  const auto& knots = scenario_.noise.temp_knots_c;
  if (knots.empty()) return 0.0;
  while (knot_ + 1 < knots.size() && knots[knot_ + 1].first <= t_s) ++knot_;
  const auto& [t0, c0] = knots[knot_];
  if (knot_ + 1 >= knots.size() || t_s <= t0) return c0;
  const auto& [t1, c1] = knots[knot_ + 1];
  return c0 + (c1 - c0) * (t_s - t0) / (t1 - t0);
}

void GyroSimulator::step(core::Sample& measured, TruthPoint& truth) {
  const NoiseModel& noise = scenario_.noise;
  const double dt_s = 1.0 / noise.rate_hz;
  const double t_s = static_cast<double>(index_) * dt_s;

  while (leg_ < scenario_.legs.size() && index_ >= leg_start_ + scenario_.legs[leg_].samples) {
    leg_start_ += scenario_.legs[leg_].samples;
    ++leg_;
  }
  static const Leg kStill{};
  const Leg& leg = leg_ < scenario_.legs.size() ? scenario_.legs[leg_] : kStill;

  if (index_ % slow_update_every_ == 0 && index_ > 0) update_slow_bias(dt_s * static_cast<double>(slow_update_every_));

  const double temp_c = noise.ambient_c + noise.warmup_rise_c * (1.0 - std::exp(-t_s / noise.warmup_tau_s)) +
                        noise.swing_c * std::sin(2.0 * std::numbers::pi * t_s / noise.swing_period_s) +
                        leg.temp_offset_c + knot_offset_c(t_s);
  const double above_c = temp_c - noise.ambient_c;
  const core::Vec3 bias_dps = noise.initial_bias_dps + noise.bias_per_c_dps * above_c +
                              noise.bias_per_c2_dps * (above_c * above_c) + slow_bias_dps_;

  for (int axis = 0; axis < 3; ++axis) {
    filtered_noise_dps_[axis] =
        lpf_alpha_ * filtered_noise_dps_[axis] + (1.0 - lpf_alpha_) * white_sigma_dps_[axis] * normal_(rng_);
  }
  core::Vec3 value = leg.rate_dps * (1.0 + noise.scale_factor_error) + bias_dps + filtered_noise_dps_;
  if (leg.vibration_dps > 0.0) {
    // A wheeled platform shakes in pitch and roll far more than in yaw.
    for (int axis = 0; axis < 3; ++axis) value[axis] += leg.vibration_dps * noise.vibration_share[axis] * normal_(rng_);
  }

  // The true heading uses the estimator's rectangle rule: rate at t_i over (t_{i-1}, t_i].
  if (index_ > 0) heading_deg_ += leg.rate_dps.z() * dt_s;

  measured.t_s = t_s;
  for (int axis = 0; axis < 3; ++axis)
    measured.rate_dps[axis] = quantise(value[axis], noise.quantum_dps, noise.full_scale_dps);
  measured.temp_c = temp_c;

  truth.t_s = t_s;
  truth.heading_deg = heading_deg_;
  truth.bias_z_dps = bias_dps.z();
  truth.rate_z_dps = leg.rate_dps.z();
  truth.temp_c = temp_c;
  truth.moving = leg.moving;
  ++index_;
}

}  // namespace headingd::drivers
