#pragma once
// The TOML configuration file (config/headingd.toml documents every key). Every error names
// the file, the line, the key, the value and what is allowed; unknown keys are rejected so a
// typo cannot silently leave a default in force.
#include <stdexcept>
#include <string>

#include "core/estimator.hpp"
#include "dds/dds_settings.hpp"
#include "hw/sensor_options.hpp"

namespace headingd::app {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Config {
  core::EstimatorSettings estimator = core::kDefaultEstimatorSettings;
  DdsSettings dds;
  SensorOptions sensor;
  std::optional<std::string> state_path;  // persisted bias and temperature model; "" = none
  double state_save_interval_s = 60.0;
  bool state_restore_heading = true;  // the heading goes on from the saved one after a restart
  // [record]: the last hours of samples as a series of recordings (pipeline/rolling_recording_sink).
  std::string record_dir;  // "" = none
  double record_split_hours = 1.0;
  double record_keep_hours = 48.0;
  std::string log_level = "info";
};

Config load_config(const std::string& path);
// Applies a --method option to the settings; false (after saying why on stderr) when unknown.
bool apply_method_option(const std::optional<std::string>& method, core::EstimatorSettings& settings);
// For tests and tools: parses TOML text; `name` stands for the file in messages.
Config parse_config(std::string_view text, const std::string& name);

}  // namespace headingd::app
