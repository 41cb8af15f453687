#include "app/replay_command.hpp"

#include <cstdio>
#include <memory>

#include "app/job.hpp"
#include "io/csv_replay.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/pacer.hpp"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"

namespace headingd::app {

int run_replay(const ReplayOptions& options) {
  JobOptions job;
  job.command = "replay";
  try {
    if (options.config_path) {
      const Config config = load_config(*options.config_path);
      job.settings = config.estimator;
      job.dds = config.dds;
    }
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitConfig;
  }
  if (!apply_method_option(options.method, job.settings)) return kExitUsage;
  if (const auto problem = pipeline::check_output_rate(options.output_rate_hz)) {
    std::fprintf(stderr, "headingd: %s\n", problem->c_str());
    return kExitUsage;
  }
  const auto speed = pipeline::parse_speed(options.speed);
  if (!speed) {
    std::fprintf(stderr, "headingd: --speed: '%s' is not max, realtime or a positive factor\n", options.speed.c_str());
    return kExitUsage;
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

  job.output = options.output;
  job.output_rate_hz = options.output_rate_hz;
  job.publish = options.publish;
  job.speed_factor = *speed;
  job.batch = 4096;
  job.wait_subscribers_s = options.wait_subscribers_s;
  job.linger_s = options.linger_s;
  job.quiet = options.quiet;
  return run_job(*source, job);
}

}  // namespace headingd::app
