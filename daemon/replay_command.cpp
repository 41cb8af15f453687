#include "daemon/replay_command.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include "core/estimator.hpp"
#include "daemon/config_file.hpp"
#include "daemon/dds_node.hpp"
#include "daemon/dds_participant.hpp"
#include "daemon/estimates_writer.hpp"
#include "daemon/exit_codes.hpp"
#include "daemon/signals.hpp"
#include "drivers/csv_replay.hpp"

namespace headingd::app {
namespace {

constexpr std::size_t kBatch = 4096;
constexpr double kNominalRateHz = 400.0;  // sizes the writer's wait buffer only

void print_summary(const drivers::SampleSource& source, const core::Estimator& estimator, double first_t_s,
                   double wall_s, std::uint64_t rows, const std::string& output) {
  const auto& last = estimator.last();
  const double span_s = last.t_s - first_t_s;
  const auto samples = static_cast<double>(estimator.samples());
  std::fprintf(stderr, "headingd replay: %s\n", source.describe().c_str());
  std::fprintf(stderr, "  samples      %llu over %.1f s (%.1f Hz)\n",
               static_cast<unsigned long long>(estimator.samples()), span_s,
               span_s > 0 ? (samples - 1.0) / span_s : 0.0);
  std::fprintf(stderr, "  method       %s; segments up to %.1f s: %llu accepted as still, %llu rejected\n",
               std::string(core::method_name(estimator.method())).c_str(), estimator.settings().segments.segment_s,
               static_cast<unsigned long long>(estimator.accepted_segments()),
               static_cast<unsigned long long>(estimator.rejected_segments()));
  const auto sigma = estimator.sigma_still_dps();
  std::fprintf(stderr, "  sigma_still  x %.4f  y %.4f  z %.4f dps\n", sigma.x(), sigma.y(), sigma.z());
  if (const auto* automatic = estimator.automatic()) {
    const auto n = automatic->noise_density_dps_rt_hz();
    std::fprintf(stderr, "  noise        x %.4f  y %.4f  z %.4f dps/sqrt(Hz) (angle random walk)\n", n.x(), n.y(),
                 n.z());
    std::fprintf(stderr, "  creep        %llu accepted segments taken back when the next one showed a creep\n",
                 static_cast<unsigned long long>(automatic->retracted_segments()));
    if (automatic->bias_recoveries() > 0)
      std::fprintf(stderr,
                   "  recovered    the bias started again %llu times from a long quiet period it could not "
                   "explain (a start-up while turning?)\n",
                   static_cast<unsigned long long>(automatic->bias_recoveries()));
    const auto& model = automatic->temperature_model(2);
    if (model.ready()) {
      std::fprintf(stderr, "  temperature  z bias slope %+.5f dps/C over a %.1f C span (%u segments)\n",
                   model.slope_dps_per_c(25.0), model.weighted_span_c(), model.points());
    } else {
      std::fprintf(stderr, "  temperature  model not in use yet (span %.1f C, %u segments)\n", model.weighted_span_c(),
                   model.points());
    }
  }
  const auto& bias = last.bias_dps;
  std::fprintf(stderr, "  bias         x %+.4f  y %+.4f  z %+.4f dps\n", bias.x(), bias.y(), bias.z());
  std::fprintf(stderr, "  heading      %+.3f deg at the end (unwrapped), sigma %.3f deg\n", last.heading_deg,
               last.heading_sigma_deg);
  std::fprintf(stderr, "  estimates    %llu rows to %s\n", static_cast<unsigned long long>(rows),
               output == "-" ? "standard output" : output.c_str());
  std::fprintf(stderr, "  speed        %.2f s wall, %.2f million samples/s, %.0fx real time\n", wall_s,
               wall_s > 0 ? samples / wall_s / 1e6 : 0.0, wall_s > 0 ? span_s / wall_s : 0.0);
}

}  // namespace

int run_replay(const ReplayOptions& options) {
  core::EstimatorSettings settings = core::kDefaultEstimatorSettings;
  DdsSettings dds_settings;
  try {
    if (options.config_path) {
      const Config config = load_config(*options.config_path);
      settings = config.estimator;
      dds_settings = config.dds;
    }
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitConfig;
  }
  if (!apply_method_option(options.method, settings)) return kExitUsage;
  if (!(options.output_rate_hz >= 0.0) || !std::isfinite(options.output_rate_hz)) {
    std::fprintf(stderr, "headingd: --output-rate must be 0 (every sample) or a positive rate in Hz\n");
    return kExitUsage;
  }

  double speed_factor = 0.0;  // 0: as fast as possible
  if (options.speed == "realtime") {
    speed_factor = 1.0;
  } else if (options.speed != "max") {
    char* end = nullptr;
    speed_factor = std::strtod(options.speed.c_str(), &end);
    if (end == options.speed.c_str() || *end != '\0' || !(speed_factor > 0.0) || !std::isfinite(speed_factor)) {
      std::fprintf(stderr, "headingd: --speed: '%s' is not max, realtime or a positive factor\n",
                   options.speed.c_str());
      return kExitUsage;
    }
  }

  std::unique_ptr<drivers::CsvReplaySource> source;
  try {
    source = std::make_unique<drivers::CsvReplaySource>(options.input);
  } catch (const drivers::OpenError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitNoInput;
  } catch (const drivers::InputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitDataError;
  }

  std::unique_ptr<DdsNode> node;
  if (options.publish) {
    try {
      node = std::make_unique<DdsNode>(dds_settings);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "headingd: DDS: %s\n", error.what());
      return kExitSoftware;
    }
    install_stop_signals();
    if (options.wait_subscribers_s > 0 && !node->wait_for_subscribers(options.wait_subscribers_s)) {
      std::fprintf(stderr, "headingd: no orientation subscriber within %.1f s; publishing anyway\n",
                   options.wait_subscribers_s);
    }
  }

  const auto started = std::chrono::steady_clock::now();
  core::Estimator estimator(settings);
  int exit_code = kExitOk;
  double first_t_s = 0.0;
  std::uint64_t rows = 0;
  try {
    CsvOut out(options.output);
    const double rows_per_second = options.output_rate_hz > 0 ? options.output_rate_hz : kNominalRateHz;
    EstimatesWriter writer(out, options.output_rate_hz,
                           static_cast<std::size_t>(std::ceil(rows_per_second * settings.segments.segment_s)));
    std::vector<core::Sample> batch(kBatch);
    try {
      double wall_offset_s = 0.0;
      StatusReport report;
      report.state = 4;  // SENSOR_REPLAY
      while (!stop_requested()) {
        const std::size_t count = source->read(batch);
        if (count == 0) break;
        if (estimator.samples() == 0) {
          first_t_s = batch[0].t_s;
          wall_offset_s = wall_now_s() - first_t_s;
        }
        for (std::size_t i = 0; i < count && !stop_requested(); ++i) {
          const core::Sample& sample = batch[i];
          if (speed_factor > 0.0) {
            // Pace by the recording's clock: sample due at start + (t - t0) / factor.
            const auto due = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                           std::chrono::duration<double>((sample.t_s - first_t_s) / speed_factor));
            if (due > std::chrono::steady_clock::now()) std::this_thread::sleep_until(due);
          }
          if (node) node->apply_commands(estimator);
          const auto& estimate = estimator.update(sample);
          writer.add(estimate);
          if (node) {
            report.samples_received = estimator.samples();
            report.uptime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            const double span = sample.t_s - first_t_s;
            report.sample_rate_hz = span > 0 ? static_cast<double>(estimator.samples() - 1) / span : 0.0;
            node->publish(estimate, estimator, report, speed_factor > 0 ? wall_offset_s : wall_now_s() - sample.t_s);
          }
        }
      }
    } catch (const drivers::InputError& error) {
      std::fprintf(stderr, "headingd: %s\n", error.what());
      std::fprintf(stderr, "headingd: stopped there; estimates up to the previous sample are kept\n");
      exit_code = kExitDataError;
    }
    writer.finish();
    out.close();
    rows = writer.rows_written();
  } catch (const OutputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitCantCreate;
  }
  if (node) {
    // Late subscribers still get the latest GyroBias and Status (transient-local) meanwhile.
    const auto linger_until = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.linger_s);
    while (!stop_requested() && std::chrono::steady_clock::now() < linger_until)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (!options.quiet) {
      std::fprintf(stderr,
                   "headingd replay: published %llu orientation messages; commands %llu accepted, %llu refused\n",
                   static_cast<unsigned long long>(node->orientation_sent()),
                   static_cast<unsigned long long>(node->commands_accepted()),
                   static_cast<unsigned long long>(node->commands_rejected()));
    }
    node.reset();  // deletes the participant: no shared-memory files left behind
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!options.quiet && estimator.samples() > 0) {
    print_summary(*source, estimator, first_t_s, wall_s, rows, options.output);
  }
  return exit_code;
}

}  // namespace headingd::app
