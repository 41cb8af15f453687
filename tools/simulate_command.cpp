#include "tools/simulate_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/csv_out.hpp"
#include "io/native_csv.hpp"
#include "service/exit_codes.hpp"
#include "sim/gyro_simulator.hpp"

namespace headingd::app {
namespace {

constexpr double kTruthRateHz = 10.0;

std::string provenance(const drivers::Scenario& s, std::uint64_t seed) {
  char text[512];
  std::snprintf(text, sizeof text,
                "# sensor: simulated ST L3GD20H (headingd simulate), +-%.0f dps, %.2f mdps/LSB\n"
                "# scenario: %s (%s)\n"
                "# seed: %llu; rate: %.1f Hz; duration: %.2f h\n"
                "# noise: ARW z %.4f x/y %.3f dps/sqrt(Hz), bias instability z %.4f dps, warm-up +%.1f C "
                "(tau %.0f s), bias/temp z %.4f dps/C\n",
                s.noise.full_scale_dps, s.noise.quantum_dps * 1000.0, s.name.c_str(), s.description.c_str(),
                static_cast<unsigned long long>(seed), s.noise.rate_hz,
                static_cast<double>(s.total_samples) / s.noise.rate_hz / 3600.0, s.noise.arw_dps_rt_hz.z(),
                s.noise.arw_dps_rt_hz.x(), s.noise.bias_instability_dps.z(), s.noise.warmup_rise_c,
                s.noise.warmup_tau_s, s.noise.bias_per_c_dps.z());
  std::string lines = text;
  if (s.noise.scale_factor_error != 0.0 || !s.noise.rate_random_walk_dps_rt_s.isZero() ||
      !s.noise.temp_knots_c.empty()) {
    std::snprintf(text, sizeof text,
                  "# also: scale factor %+.3f %%, bias/temp^2 z %+.2e dps/C^2, rate random walk z %.1e dps/sqrt(s), "
                  "ambient %.1f C, %zu temperature knots\n",
                  100.0 * s.noise.scale_factor_error, s.noise.bias_per_c2_dps.z(),
                  s.noise.rate_random_walk_dps_rt_s.z(), s.noise.ambient_c, s.noise.temp_knots_c.size());
    lines += text;
  }
  return lines;
}

}  // namespace

std::string scenario_names() {
  std::string known;
  for (const auto& [name, description] : drivers::scenario_list()) known += (known.empty() ? "" : ", ") + name;
  return known;
}

int run_simulate(const SimulateOptions& options) {
  auto scenario = drivers::build_scenario(options.scenario, options.seed, options.hours);
  if (!scenario) {
    std::fprintf(stderr, "headingd: --scenario: unknown scenario '%s' (known: %s)\n", options.scenario.c_str(),
                 scenario_names().c_str());
    return kExitUsage;
  }
  if (!(options.hours >= 0.0) || !std::isfinite(options.hours)) {
    std::fprintf(stderr, "headingd: --hours must be a positive number of hours\n");
    return kExitUsage;
  }
  if (options.bias_per_c_dps) {
    // NaN fails the range test too: a given value is never taken as "not given".
    if (!(std::abs(*options.bias_per_c_dps) <= 1.0)) {
      std::fprintf(stderr, "headingd: --bias-per-c must lie within [-1, 1] dps per degC\n");
      return kExitUsage;
    }
    scenario->noise.bias_per_c_dps = core::Vec3::Constant(*options.bias_per_c_dps);
  }
  std::error_code error;
  std::filesystem::create_directories(options.output_dir, error);
  if (error) {
    std::fprintf(stderr, "headingd: cannot create %s: %s\n", options.output_dir.c_str(), error.message().c_str());
    return kExitCantCreate;
  }

  drivers::GyroSimulator simulator(*scenario, options.seed);
  const std::string header = provenance(simulator.scenario(), options.seed);
  try {
    RecordingWriter imu((std::filesystem::path(options.output_dir) / "imu.csv").string(), header,
                        RecordingPrecision{.time_decimals = 6, .temp_decimals = 2});
    CsvOut truth((std::filesystem::path(options.output_dir) / "truth.csv").string());
    truth.text(header.substr(0, header.size() - 1));
    truth.end_line();
    truth.line("time_s,heading_deg,bias_z_dps,moving");
    const auto truth_every = static_cast<std::uint64_t>(std::llround(scenario->noise.rate_hz / kTruthRateHz));
    core::Sample sample;
    drivers::TruthPoint point;
    for (std::uint64_t i = 0; !simulator.done(); ++i) {
      simulator.step(sample, point);
      imu.add(sample);
      if (i % truth_every == 0) {
        truth.number(point.t_s, 6).number(point.heading_deg, 6).number(point.bias_z_dps, 6).integer(point.moving);
        truth.end_line();
      }
    }
    imu.close();
    truth.close();
  } catch (const OutputError& failure) {
    std::fprintf(stderr, "headingd: %s\n", failure.what());
    return kExitCantCreate;
  }
  std::fprintf(stderr, "headingd simulate: %s, seed %llu, %llu samples -> %s/imu.csv, truth.csv\n",
               scenario->name.c_str(), static_cast<unsigned long long>(options.seed),
               static_cast<unsigned long long>(scenario->total_samples), options.output_dir.c_str());
  return kExitOk;
}

}  // namespace headingd::app
