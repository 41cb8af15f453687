#pragma once
// A MEMS gyro as the paper measured it: white noise (angle random walk) through the chip's
// low-pass, bias instability as a sum of Gauss-Markov processes (a 1/f-like flat Allan
// floor), a warm-up temperature transient driving the bias, vibration while moving,
// quantisation to the LSB and clipping at full scale.
#include <array>
#include <cstdint>
#include <random>

#include "sim/scenarios.hpp"

namespace headingd::drivers {

struct TruthPoint {
  double t_s = 0.0;
  double heading_deg = 0.0;
  double bias_z_dps = 0.0;  // true bias (temperature + instability), no white noise
  double rate_z_dps = 0.0;  // true turn rate
  double temp_c = 0.0;
  bool moving = false;
};

class GyroSimulator {
 public:
  GyroSimulator(Scenario scenario, std::uint64_t seed);

  bool done() const { return index_ >= scenario_.total_samples; }
  // Produces the next measured sample and the truth at the same instant.
  void step(core::Sample& measured, TruthPoint& truth);
  const Scenario& scenario() const { return scenario_; }

 private:
  static constexpr int kMarkovTerms = 3;
  void update_slow_bias(double dt_s);

  Scenario scenario_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uint64_t index_ = 0;
  std::size_t leg_ = 0;
  std::uint64_t leg_start_ = 0;
  double heading_deg_ = 0.0;
  double lpf_alpha_ = 0.0;
  core::Vec3 white_sigma_dps_ = core::Vec3::Zero();
  core::Vec3 filtered_noise_dps_ = core::Vec3::Zero();
  std::array<core::Vec3, kMarkovTerms> markov_dps_{};
  std::array<double, kMarkovTerms> markov_tau_s_{20.0, 200.0, 2000.0};
  core::Vec3 slow_bias_dps_ = core::Vec3::Zero();
  core::Vec3 walk_bias_dps_ = core::Vec3::Zero();  // rate random walk (drawn only when configured)
  std::uint64_t slow_update_every_ = 1;
  std::size_t knot_ = 0;  // temperature knot at or before now
  double knot_offset_c(double t_s);
};

}  // namespace headingd::drivers
