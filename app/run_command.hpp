#pragma once
#include <optional>
#include <set>
#include <string>

#include "hw/sensor_options.hpp"

namespace headingd::app {

struct RunOptions {
  SensorOptions sensor;
  std::set<std::string> sensor_given;  // sensor options given on the command line (win over the file)
  std::optional<std::string> config_path;
  std::optional<std::string> method;
  std::optional<std::string> output;  // estimates CSV
  double output_rate_hz = 10.0;
  std::optional<std::string> record_path;  // also write what the sensor delivers (native CSV)
  // A rolling recording (overrides [record]): directory, hours per file, hours kept.
  std::optional<std::string> record_dir;
  std::optional<double> record_split_hours, record_keep_hours;
  std::optional<std::string> state_path;  // overrides [state] path
  double duration_s = 0.0;                // 0: until SIGINT or SIGTERM
  bool publish = true;                    // DDS
  // A recording instead of the sensor, paced by `speed` (max, realtime or a factor).
  std::optional<std::string> recording;
  std::string speed = "realtime";
};

// `headingd run`: the live sensor through the same pipeline as replay, publishing over DDS,
// speaking systemd's notify protocol, keeping its bias across restarts.
int run_live(const RunOptions& options);
// `headingd record`: what the sensor delivers, as a native CSV that replays.
// `record`: the sensor from [sensor] of --config (if given) with the command line's options on top.
int run_record(const RunOptions& options, const std::string& output, double duration_s);

}  // namespace headingd::app
