#include "daemon/run_command.hpp"

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <vector>

#include "core/estimator.hpp"
#include "daemon/config_file.hpp"
#include "daemon/csv_out.hpp"
#include "daemon/estimates_writer.hpp"
#include "daemon/exit_codes.hpp"
#include "daemon/signals.hpp"

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

int run_live(const RunOptions& options) {
  core::EstimatorSettings settings = core::kDefaultEstimatorSettings;
  try {
    if (options.config_path) settings = load_config(*options.config_path).estimator;
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitConfig;
  }
  if (options.method) {
    const auto method = core::parse_method(*options.method);
    if (!method) {
      std::fprintf(stderr, "headingd: --method: '%s' is not a method (use auto, a, b or c)\n", options.method->c_str());
      return kExitUsage;
    }
    settings.method = *method;
  }
  int exit_code = kExitOk;
  auto source = open_source(options.sensor, exit_code);
  if (!source) return exit_code;
  install_stop_signals();
  source->driver().set_stop_flag(&stop_flag());

  core::Estimator estimator(settings);
  try {
    std::unique_ptr<CsvOut> out;
    std::unique_ptr<EstimatesWriter> writer;
    if (options.output) {
      out = std::make_unique<CsvOut>(*options.output);
      writer = std::make_unique<EstimatesWriter>(*out, options.output_rate_hz,
                                                 static_cast<std::size_t>(std::ceil(400.0 * settings.segments.segment_s)));
    }
    std::unique_ptr<Recorder> recorder;
    if (options.record_path) recorder = std::make_unique<Recorder>(*options.record_path, source->header_comment());
    std::vector<core::Sample> batch(64);
    double first_t_s = NAN;
    while (const std::size_t n = source->driver().read(batch)) {
      for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(first_t_s)) first_t_s = batch[i].t_s;
        if (recorder) recorder->add(batch[i]);
        const auto& estimate = estimator.update(batch[i]);
        if (writer) writer->add(estimate);
      }
      if (options.duration_s > 0 && batch[n - 1].t_s - first_t_s >= options.duration_s) break;
    }
    if (writer) writer->finish();
    if (out) out->close();
    if (recorder) recorder->finish(source->driver());
  } catch (const OutputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitCantCreate;
  }
  const auto& last = estimator.last();
  std::fprintf(stderr, "headingd run: %s\n", stop_requested() ? "stopped by signal" : "done");
  print_counters(source->driver());
  std::fprintf(stderr, "  estimator    %s; heading %+.3f deg, sigma %.3f deg; bias z %+.4f dps\n",
               std::string(core::method_name(estimator.method())).c_str(), last.heading_deg, last.heading_sigma_deg,
               last.bias_dps.z());
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
