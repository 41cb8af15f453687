#include "app/run_command.hpp"

#include <cstdio>
#include <memory>

#include "app/job.hpp"
#include "app/sensor.hpp"
#include "hw/iio_device.hpp"
#include "io/csv_replay.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/pacer.hpp"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"
#include "service/input_errors.hpp"
#include "service/log.hpp"
#include "service/signals.hpp"

namespace headingd::app {
namespace {

SensorOptions merged_sensor(const SensorOptions& file, const RunOptions& options) {
  SensorOptions s = file;
  const SensorOptions& cli = options.sensor;
  const auto given = [&](const char* name) { return options.sensor_given.count(name) > 0; };
  if (given("--bus")) s.bus = cli.bus;
  if (given("--address")) s.address = cli.address;
  if (given("--rate")) s.rate_hz = cli.rate_hz;
  if (given("--bandwidth")) s.bandwidth = cli.bandwidth;
  if (given("--full-scale")) s.full_scale_dps = cli.full_scale_dps;
  if (given("--watermark")) s.watermark = cli.watermark;
  if (given("--gpio-chip")) s.gpio_chip = cli.gpio_chip;
  if (given("--gpio-line")) s.gpio_line = cli.gpio_line;
  if (given("--int2-active-low")) s.int2_active_low = cli.int2_active_low;
  s.simulated_chip = cli.simulated_chip;
  if (s.simulated_chip) s.kind = "l3gd20h";  // the simulator is an L3GD20H
  s.sim_seed = cli.sim_seed;
  s.sim_rate_error = cli.sim_rate_error;
  s.sim_realtime = cli.sim_realtime;
  s.sim_dead_after_s = cli.sim_dead_after_s;
  s.sim_nack_at_s = cli.sim_nack_at_s;
  s.sim_stuck_at_s = cli.sim_stuck_at_s;
  return s;
}

// The sensor, with the driver's warnings going to our log and SIGTERM ending its waits; null
// (and `code`, the exit code) when it cannot be opened.
std::unique_ptr<Sensor> open_live(const SensorOptions& sensor, int& code) {
  code = kExitNoInput;
  try {
    SensorHooks hooks;
    hooks.stop = &stop_flag();
    hooks.log = [](int priority, const std::string& key, const std::string& text) {
      log(static_cast<LogPriority>(priority), key, text);
    };
    return open_sensor(sensor, hooks);
  } catch (const drivers::IioReadOnlyError& error) {
    report(LogPriority::Error, std::string(error.what()));
    code = kExitConfig;  // the service's sandbox, not the sensor: a restart would meet it again
    return nullptr;
  } catch (const std::exception& error) {
    report(LogPriority::Error, std::string(error.what()));
    return nullptr;
  }
}

std::string comments_of(const drivers::CsvReplaySource& recording) {
  std::string text;
  for (const auto& line : recording.comments()) text += "#" + line + "\n";
  return text;
}

// --config, if given: 0, or the exit code after saying why.
int load_run_config(const RunOptions& options, Config& config) {
  try {
    if (options.config_path) config = load_config(*options.config_path);
  } catch (const ConfigError& error) {
    report(LogPriority::Error, std::string(error.what()));
    return kExitConfig;
  }
  return 0;
}

// The sensor [sensor] and the command line name (run and record alike): 0, or the exit code.
int open_configured_sensor(const Config& config, const RunOptions& options, std::unique_ptr<Sensor>& sensor) {
  const SensorOptions sensor_options = merged_sensor(config.sensor, options);
  if (const auto unknown = unknown_sensor_kind(sensor_options.kind); !unknown.empty()) {
    report(LogPriority::Error, options.config_path.value_or("") + ": " + unknown);
    return kExitConfig;
  }
  int code = 0;
  sensor = open_live(sensor_options, code);
  return sensor ? 0 : code;
}

}  // namespace

int run_live(const RunOptions& options) {
  Config config;
  if (const int code = load_run_config(options, config)) return code;
  JobOptions job;
  job.command = "run";
  job.settings = config.estimator;
  if (!apply_method_option(options.method, job.settings)) return kExitUsage;
  if (const int code = set_rate_and_speed(options.output_rate_hz, options.speed, job)) return code;
  LogPriority level;
  if (parse_log_level(config.log_level, level)) set_log_level(level);
  job.output = options.output;
  job.record_path = options.record_path;
  job.rolling.dir = options.record_dir.value_or(config.record_dir);
  job.rolling.split_hours = options.record_split_hours.value_or(config.record_split_hours);
  job.rolling.keep_hours = options.record_keep_hours.value_or(config.record_keep_hours);
  if (job.record_path && !job.rolling.dir.empty()) {
    report(LogPriority::Error, "--record and a rolling recording (--record-dir, or [record] dir) together: choose one");
    return kExitUsage;
  }
  if (options.state_path && options.state_path->empty()) {
    report(LogPriority::Error, "--state needs a file name (to run without saved state, give none)");
    return kExitUsage;
  }
  job.state_path = options.state_path ? options.state_path : config.state_path;
  if (job.state_path && job.state_path->empty()) job.state_path.reset();  // [state] path = "": none
  job.state_save_interval_s = config.state_save_interval_s;
  job.state_restore_heading = config.state_restore_heading;
  job.publish = options.publish;
  job.files_expendable = options.publish;  // the vehicle's heading outlives a full disk
  job.dds = config.dds;
  job.duration_s = options.duration_s;
  job.config_path = options.config_path;
  job.method = options.method;

  if (options.recording) {
    std::unique_ptr<drivers::CsvReplaySource> recording;  // standing in for the sensor
    if (const int code =
            report_input_errors([&] { recording = std::make_unique<drivers::CsvReplaySource>(*options.recording); }))
      return code;
    job.batch = 4096;
    job.record_comments = comments_of(*recording);
    job.input_paths = {*options.recording};
    job.progress = [&recording] { return recording->fraction_read(); };
    return run_job(*recording, job);
  }
  job.speed_factor = 0.0;  // a sensor paces itself
  std::unique_ptr<Sensor> sensor;
  if (const int code = open_configured_sensor(config, options, sensor)) return code;
  job.record_comments = sensor->header_comment();
  return run_job(sensor->source(), job);
}

int run_record(const RunOptions& options, const std::string& output, double duration_s) {
  Config config;
  if (const int code = load_run_config(options, config)) return code;
  std::unique_ptr<Sensor> sensor;
  if (const int code = open_configured_sensor(config, options, sensor)) return code;
  JobOptions job;
  job.command = "record";
  job.record_path = output;
  job.record_comments = sensor->header_comment();
  job.duration_s = duration_s;
  return run_job(sensor->source(), job);
}

}  // namespace headingd::app
