#pragma once
// Motion scenarios for the gyro simulator: a platform's true rate as a list of legs, each
// a whole number of samples long so that the true heading is exactly the rectangle-rule
// sum of the true rates (the estimator's error is then the sensor's doing alone).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/sample.hpp"

namespace headingd::drivers {

struct NoiseModel {
  double rate_hz = 400.0;  // output data rate the file is written at
  // Angle random walk per axis, dps/sqrt(Hz): the paper's Allan analysis (z 0.011, x/y ~0.1).
  core::Vec3 arw_dps_rt_hz{0.1, 0.1, 0.011};
  double lpf_hz = 50.0;  // chip low-pass on the noise (bandwidth setting)
  // Bias instability, dps (paper: 3.58 deg/h on z), shaped as a sum of Gauss-Markov terms.
  core::Vec3 bias_instability_dps{0.003, 0.003, 0.001};
  core::Vec3 initial_bias_dps{0.35, -0.21, -0.455};  // paper: z mean -52 LSB = -0.455 dps
  core::Vec3 bias_per_c_dps{0.004, -0.003, 0.0012};  // zero-rate change with temperature
  double ambient_c = 22.0;
  double warmup_rise_c = 15.0;                // self-heating after power-on
  double warmup_tau_s = 3600.0;               // paper: about 4 h to settle (~4 time constants)
  double swing_c = 0.0;                       // amplitude of a slow temperature swing, degC
  double swing_period_s = 1800.0;             // its period, s
  core::Vec3 vibration_share{1.0, 1.0, 0.3};  // of a leg's vibration, per axis
  double quantum_dps = 0.00875;               // 8.75 mdps/LSB at +-245 dps
  double full_scale_dps = 245.0;
  // Zero in the named scenarios; the random one draws them.
  core::Vec3 bias_per_c2_dps = core::Vec3::Zero();            // quadratic part, dps/C^2 (about ambient)
  core::Vec3 rate_random_walk_dps_rt_s = core::Vec3::Zero();  // the bias's own random walk
  double scale_factor_error = 0.0;                            // measured = true * (1 + this) + bias
  // Added to the warm-up and swing: a piecewise-linear temperature offset, (time s, degC) knots.
  std::vector<std::pair<double, double>> temp_knots_c;
};

struct Leg {
  std::uint64_t samples = 0;
  core::Vec3 rate_dps = core::Vec3::Zero();  // true rate during the leg
  double vibration_dps = 0.0;                // extra measured noise (wheels, floor)
  bool moving = false;
  // Optional temperature swing added to the warm-up curve during the leg, degC.
  double temp_offset_c = 0.0;
};

struct Scenario {
  std::string name;
  std::string description;
  NoiseModel noise;
  std::vector<Leg> legs;  // after the last leg the platform stands still
  std::uint64_t total_samples = 0;
};

// Names accepted by build_scenario, with a one-line description each.
std::vector<std::pair<std::string, std::string>> scenario_list();
// nullopt for an unknown name. `hours` <= 0 selects the scenario's own length.
std::optional<Scenario> build_scenario(std::string_view name, std::uint64_t seed, double hours);

}  // namespace headingd::drivers
