#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace headingd::app {

struct SimulateOptions {
  std::string scenario;
  std::uint64_t seed = 1;
  std::string output_dir;
  double hours = 0.0;  // 0: the scenario's own length
  // The zero-rate level's change with temperature on every axis, dps/C, in place of the
  // scenario's own (unset: the scenario's). The L3GD20H datasheet's typical figure is +-0.04.
  std::optional<double> bias_per_c_dps;
};

// The scenarios' names, comma-separated (for help and errors).
std::string scenario_names();

// Writes OUTPUT_DIR/imu.csv (native CSV at the sensor rate, quantised like the chip) and
// OUTPUT_DIR/truth.csv (time_s,heading_deg,bias_z_dps,moving at 10 Hz).
int run_simulate(const SimulateOptions& options);

}  // namespace headingd::app
