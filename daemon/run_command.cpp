#include "daemon/run_command.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "core/estimator.hpp"
#include "daemon/config_file.hpp"
#include "daemon/csv_out.hpp"
#include "daemon/dds_node.hpp"
#include "daemon/dds_participant.hpp"
#include "daemon/estimates_writer.hpp"
#include "daemon/exit_codes.hpp"
#include "daemon/log.hpp"
#include "daemon/notify.hpp"
#include "daemon/signals.hpp"
#include "daemon/state_file.hpp"

namespace headingd::app {
namespace {

// Writes samples as the native CSV that `replay` reads: 9 decimals of time (the driver's
// nanoseconds) and 5 of rate (a multiple of the LSB exactly), so a replay sees the very same
// doubles the live run saw.
class Recorder {
 public:
  Recorder(const std::string& path, const std::string& header) : out_(path) {
    out_.text(header.substr(0, header.empty() ? 0 : header.size() - 1));
    out_.end_line();
    out_.line("time_s,gx_dps,gy_dps,gz_dps,temp_c");
  }
  void add(const core::Sample& s) {
    out_.number(s.t_s, 9);
    for (int axis = 0; axis < 3; ++axis) out_.number(s.rate_dps[axis], 5);
    out_.number(s.temp_c, 1);
    out_.end_line();
  }
  void finish(const drivers::L3gd20h& driver) {
    char text[160];
    std::snprintf(text, sizeof text, "# measured output rate %.3f Hz; %llu samples, %llu lost", driver.rate_hz(),
                  static_cast<unsigned long long>(driver.counters().samples),
                  static_cast<unsigned long long>(driver.counters().lost_samples));
    out_.line(text);
    out_.close();
  }

 private:
  CsvOut out_;
};

void print_counters(const drivers::L3gd20h& driver) {
  const auto& c = driver.counters();
  std::fprintf(stderr,
               "  sensor       %s\n  rate         %.3f Hz measured\n  counters     %llu samples, %llu lost in %llu "
               "overruns, %llu bus errors, %llu recoveries, %llu chip resets, %llu stuck, %llu wake-ups, %llu "
               "timeouts\n",
               driver.describe().c_str(), driver.rate_hz(), static_cast<unsigned long long>(c.samples),
               static_cast<unsigned long long>(c.lost_samples), static_cast<unsigned long long>(c.overruns),
               static_cast<unsigned long long>(c.bus_errors), static_cast<unsigned long long>(c.recoveries),
               static_cast<unsigned long long>(c.chip_resets), static_cast<unsigned long long>(c.stuck_events),
               static_cast<unsigned long long>(c.wakeups), static_cast<unsigned long long>(c.timeouts));
}

std::unique_ptr<LiveSource> open_source(const SensorOptions& sensor, int& exit_code) {
  try {
    return std::make_unique<LiveSource>(sensor);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    exit_code = kExitNoInput;
    return nullptr;
  }
}

}  // namespace

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
  s.sim_seed = cli.sim_seed;
  s.sim_rate_error = cli.sim_rate_error;
  s.sim_realtime = cli.sim_realtime;
  s.sim_dead_after_s = cli.sim_dead_after_s;
  return s;
}

SavedState snapshot(const core::Estimator& estimator) {
  SavedState state;
  const auto& last = estimator.last();
  state.bias_dps = last.bias_dps;
  state.bias_sigma_dps = last.bias_sigma_dps.allFinite() ? last.bias_sigma_dps : core::Vec3::Constant(0.01);
  state.temp_c = std::numeric_limits<double>::quiet_NaN();
  if (const auto* a = estimator.automatic()) {
    state.sigma_still_dps = a->sigma_still_dps();
    state.arw_dps_rt_hz = a->noise_density_dps_rt_hz();
    for (int axis = 0; axis < 3; ++axis) {
      state.temperature_sums[static_cast<std::size_t>(axis)] = a->temperature_model(axis).sums();
      state.temperature_points[static_cast<std::size_t>(axis)] = a->temperature_model(axis).points();
    }
  }
  state.saved_unix_s = wall_now_s();
  return state;
}

void restore(core::Estimator& estimator, const SavedState& state) {
  estimator.restore_bias(state.bias_dps, state.bias_sigma_dps);
  if (auto* a = estimator.automatic_mutable()) {
    a->set_noise(state.sigma_still_dps, state.arw_dps_rt_hz);
    for (int axis = 0; axis < 3; ++axis) {
      a->restore_temperature_model(axis, state.temperature_sums[static_cast<std::size_t>(axis)],
                                   state.temperature_points[static_cast<std::size_t>(axis)]);
    }
  }
}

void save_quietly(const std::optional<std::string>& path, const core::Estimator& estimator) {
  if (!path || estimator.in_startup()) return;
  try {
    save_state(*path, snapshot(estimator));
  } catch (const StateError& error) {
    log(LogPriority::Warning, "state write", error.what());
  }
}

// SIGHUP: new estimator settings and log level; heading, bias, noise figures and the
// temperature model carry over, so nothing learned is lost.
void reload(const std::optional<std::string>& config_path, const std::optional<std::string>& method,
            std::unique_ptr<core::Estimator>& estimator) {
  if (!config_path) {
    log(LogPriority::Notice, "reload", "SIGHUP: no configuration file to reload");
    return;
  }
  Config config;
  try {
    config = load_config(*config_path);
  } catch (const ConfigError& error) {
    log(LogPriority::Error, "reload", std::string("SIGHUP: ") + error.what() + "; keeping the running configuration");
    return;
  }
  core::EstimatorSettings settings = config.estimator;
  if (method) settings.method = estimator->method();  // the command line still wins
  const SavedState kept = snapshot(*estimator);
  const double heading_deg = estimator->last().heading_deg;
  const double sigma_deg = estimator->last().heading_sigma_deg;
  auto next = std::make_unique<core::Estimator>(settings);
  restore(*next, kept);
  next->set_heading(heading_deg, std::isfinite(sigma_deg) ? sigma_deg * sigma_deg : 0.0);
  estimator = std::move(next);
  LogPriority level;
  if (parse_log_level(config.log_level, level)) set_log_level(level);
  log(LogPriority::Notice, "reload",
      "SIGHUP: configuration reloaded from " + *config_path + " (method " +
          std::string(core::method_name(settings.method)) + ", log level " + config.log_level +
          "); heading and bias kept");
}

}  // namespace

int run_live(const RunOptions& options) {
  Config config;
  try {
    if (options.config_path) config = load_config(*options.config_path);
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitConfig;
  }
  core::EstimatorSettings settings = config.estimator;
  if (!apply_method_option(options.method, settings)) return kExitUsage;
  const std::optional<std::string> state_path = options.state_path ? options.state_path : config.state_path;
  LogPriority level;
  if (parse_log_level(config.log_level, level)) set_log_level(level);

  // Start-up, in order; shutdown undoes it in reverse.
  install_stop_signals();
  Notifier notifier;
  notifier.status("starting: opening the sensor");
  int exit_code = kExitOk;
  auto source = open_source(merged_sensor(config.sensor, options), exit_code);
  if (!source) return exit_code;
  source->driver().set_stop_flag(&stop_flag());
  source->driver().set_logger([](int priority, const std::string& key, const std::string& text) {
    log(static_cast<LogPriority>(priority), key, text);
  });

  auto estimator_owner = std::make_unique<core::Estimator>(settings);
  if (state_path) {
    try {
      restore(*estimator_owner, load_state(*state_path));
      log(LogPriority::Info, "state", "bias restored from " + *state_path);
    } catch (const StateError& error) {
      log(LogPriority::Notice, "state", error.what());
    }
  }
  std::unique_ptr<DdsNode> node;
  if (options.publish) {
    try {
      node = std::make_unique<DdsNode>(config.dds);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "headingd: DDS: %s\n", error.what());
      return kExitSoftware;
    }
  }

  const auto started = std::chrono::steady_clock::now();
  auto last_save = started;
  auto last_status = started;
  try {
    std::unique_ptr<CsvOut> out;
    std::unique_ptr<EstimatesWriter> writer;
    if (options.output) {
      out = std::make_unique<CsvOut>(*options.output);
      writer = std::make_unique<EstimatesWriter>(
          *out, options.output_rate_hz, static_cast<std::size_t>(std::ceil(400.0 * settings.segments.segment_s)));
    }
    std::unique_ptr<Recorder> recorder;
    if (options.record_path) recorder = std::make_unique<Recorder>(*options.record_path, source->header_comment());
    std::vector<core::Sample> batch(64);
    double first_t_s = NAN;
    double wall_offset_s = 0.0;
    StatusReport report;
    std::uint64_t recoveries_seen = 0;  // of the bias (auto), to warn once per recovery
    while (const std::size_t n = source->driver().read(batch)) {
      const auto& counters = source->driver().counters();
      for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(first_t_s)) {
          first_t_s = batch[i].t_s;
          wall_offset_s = wall_now_s() - first_t_s;
        }
        if (recorder) recorder->add(batch[i]);
        if (node) {
          node->apply_commands(*estimator_owner);
        }
        const auto& estimate = estimator_owner->update(batch[i]);
        if (writer) writer->add(estimate);
        if (const auto* automatic = estimator_owner->automatic()) {
          if (automatic->bias_recoveries() > recoveries_seen) {
            char text[300];
            std::snprintf(text, sizeof text,
                          "the bias restarted from a long quiet period it could not explain (a start-up while "
                          "turning, or a wrong saved bias): heading sigma now %.1f deg; a heading fix "
                          "(HeadingCommand set-heading) restores it",
                          estimate.heading_sigma_deg);
            log(LogPriority::Warning, "bias-recovery", text);
          }
          recoveries_seen = automatic->bias_recoveries();
        }
        if (node) {
          report.state = counters.recoveries > 0 && counters.samples < 400 ? 2 : 1;  // DEGRADED right after a fault
          report.sample_rate_hz = source->driver().rate_hz();
          report.samples_received = counters.samples;
          report.samples_dropped = counters.lost_samples;
          report.bus_errors = counters.bus_errors;
          report.fifo_overruns = counters.overruns;
          report.uptime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
          node->publish(estimate, *estimator_owner, report, wall_offset_s);
        }
      }
      if (take_reload_request()) reload(options.config_path, options.method, estimator_owner);
      notifier.ready();  // after the first good sample
      notifier.sample_loop_alive();
      const auto now = std::chrono::steady_clock::now();
      if (now - last_status >= std::chrono::seconds(10)) {
        last_status = now;
        char text[200];
        std::snprintf(text, sizeof text,
                      "heading %.2f deg (sigma %.2f), bias z %+.4f dps, %llu samples, %llu bus errors",
                      estimator_owner->last().heading_deg, estimator_owner->last().heading_sigma_deg,
                      estimator_owner->last().bias_dps.z(), static_cast<unsigned long long>(counters.samples),
                      static_cast<unsigned long long>(counters.bus_errors));
        notifier.status(text);
      }
      if (now - last_save >= std::chrono::duration<double>(config.state_save_interval_s)) {
        last_save = now;
        save_quietly(state_path, *estimator_owner);
      }
      if (options.duration_s > 0 && batch[n - 1].t_s - first_t_s >= options.duration_s) break;
    }
    notifier.stopping();
    save_quietly(state_path, *estimator_owner);
    if (writer) writer->finish();
    if (out) out->close();
    if (recorder) recorder->finish(source->driver());
  } catch (const OutputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitCantCreate;
  }
  node.reset();
  const auto& last = estimator_owner->last();
  std::fprintf(stderr, "headingd run: %s\n", stop_requested() ? "stopped by signal" : "done");
  print_counters(source->driver());
  std::fprintf(stderr, "  estimator    %s; heading %+.3f deg, sigma %.3f deg; bias z %+.4f dps\n",
               std::string(core::method_name(estimator_owner->method())).c_str(), last.heading_deg,
               last.heading_sigma_deg, last.bias_dps.z());
  return kExitOk;
}

int run_record(const SensorOptions& sensor, const std::string& output, double duration_s) {
  int exit_code = kExitOk;
  auto source = open_source(sensor, exit_code);
  if (!source) return exit_code;
  install_stop_signals();
  source->driver().set_stop_flag(&stop_flag());
  try {
    Recorder recorder(output, source->header_comment());
    std::vector<core::Sample> batch(64);
    double first_t_s = NAN;
    while (const std::size_t n = source->driver().read(batch)) {
      for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(first_t_s)) first_t_s = batch[i].t_s;
        recorder.add(batch[i]);
      }
      if (duration_s > 0 && batch[n - 1].t_s - first_t_s >= duration_s) break;
    }
    recorder.finish(source->driver());
  } catch (const OutputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitCantCreate;
  }
  std::fprintf(stderr, "headingd record: %s -> %s\n", stop_requested() ? "stopped by signal" : "done", output.c_str());
  print_counters(source->driver());
  return kExitOk;
}

}  // namespace headingd::app
