#include "app/replay_command.hpp"

#include <sys/stat.h>

#include <cstdio>
#include <memory>

#include "app/job.hpp"
#include "io/csv_replay.hpp"
#include "io/joined_replay.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/pacer.hpp"
#include "pipeline/read_ahead.hpp"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"
#include "service/input_errors.hpp"

namespace headingd::app {

namespace {

template <typename FileSource>
int run_read_ahead(FileSource& source, JobOptions& job) {
  pipeline::ReadAheadSource ahead(source, [&source] { return source.fraction_read(); });
  job.progress = [&ahead] { return ahead.fraction_read(); };
  return run_job(ahead, job);
}

}  // namespace

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
  if (const int code = set_rate_and_speed(options.output_rate_hz, options.speed, job)) return code;

  job.output = options.output;
  job.input_paths = options.joined.empty() ? std::vector<std::string>{options.input} : options.joined;
  job.publish = options.publish;
  job.batch = 4096;
  job.wait_subscribers_s = options.wait_subscribers_s;
  job.linger_s = options.linger_s;
  job.quiet = options.quiet;
  if (!options.joined.empty()) {
    std::unique_ptr<drivers::JoinedReplaySource> joined;
    if (const int code =
            report_input_errors([&] { joined = std::make_unique<drivers::JoinedReplaySource>(options.joined); }))
      return code;
    const int code = run_read_ahead(*joined, job);
    for (const auto& boundary : joined->run_boundaries())
      std::fprintf(stderr,
                   "headingd: --join: %s starts another run of the recorder (it names another run, or the file before "
                   "it ends its run); "
                   "the estimator carried on across the %.1f s between, where the daemon had restarted from its "
                   "state file\n",
                   boundary.file.c_str(), boundary.gap_s);
    for (const auto& part : joined->damaged_parts())
      std::fprintf(stderr, "headingd: --join: %s (what it held before that was replayed; the replay went on)\n",
                   part.error.c_str());
    return code == kExitOk && !joined->damaged_parts().empty() ? kExitDataError : code;
  }
  std::unique_ptr<drivers::CsvReplaySource> source;
  if (const int code = report_input_errors([&] { source = std::make_unique<drivers::CsvReplaySource>(options.input); }))
    return code;
  // A file is parsed on a second thread while this one estimates; a pipe or a terminal is read
  // here, where a stop can end a read that waits.
  struct stat info {};
  if (::stat(options.input.c_str(), &info) == 0 && S_ISREG(info.st_mode)) return run_read_ahead(*source, job);
  job.progress = [&source] { return source->fraction_read(); };
  return run_job(*source, job);
}

}  // namespace headingd::app
