#include "app/job.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include "app/summary.hpp"
#include "dds/dds_node.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_out.hpp"
#include "pipeline/dds_sink.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/expendable_sink.hpp"
#include "pipeline/pacer.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/progress_sink.hpp"
#include "pipeline/recording_sink.hpp"
#include "pipeline/service_sink.hpp"
#include "pipeline/state_sink.hpp"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"
#include "service/log.hpp"
#include "service/notify.hpp"
#include "service/signals.hpp"

namespace headingd::app {
namespace {

int exit_code(pipeline::Ending ending) {
  switch (ending) {
    case pipeline::Ending::EndOfInput:
    case pipeline::Ending::Duration:
    case pipeline::Ending::Signal:
    case pipeline::Ending::OutputClosed:
      return kExitOk;
    case pipeline::Ending::BadInput:
      return kExitDataError;
    case pipeline::Ending::SourceFailed:
      return kExitIoError;
    case pipeline::Ending::OutputFailed:
      return kExitCantCreate;
    case pipeline::Ending::Refused:
      return kExitTempFail;
  }
  return kExitSoftware;
}

// SIGHUP: new estimator settings and log level; heading, bias, noise figures and the
// temperature model carry over, so nothing learned is lost. Null: keep the running one.
std::unique_ptr<core::Estimator> reload(const JobOptions& options, const core::Estimator& running) {
  if (!options.config_path) {
    log(LogPriority::Notice, "reload", "SIGHUP: no configuration file to reload");
    return nullptr;
  }
  Config config;
  try {
    config = load_config(*options.config_path);
  } catch (const ConfigError& error) {
    // Keyed by the error itself: a different mistake later is reported even after a burst.
    log(LogPriority::Error, std::string("reload ") + error.what(),
        std::string("SIGHUP: ") + error.what() + "; keeping the running configuration");
    return nullptr;
  }
  core::EstimatorSettings settings = config.estimator;
  if (options.method) settings.method = running.method();  // the command line still wins
  auto next = std::make_unique<core::Estimator>(settings);
  next->restore(running.learned());                          // bias, models, heading with its sigma and fix offset
  next->set_motion_hint(running.diagnostics().motion_hint);  // the vehicle's last word still holds
  LogPriority level;
  if (parse_log_level(config.log_level, level)) set_log_level(level);
  log(LogPriority::Notice, "reload",
      "SIGHUP: configuration reloaded from " + *options.config_path + " (method " +
          std::string(core::method_name(settings.method)) + ", log level " + config.log_level +
          "); heading and bias kept");
  return next;
}

void linger(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!stop_requested() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

}  // namespace

int set_rate_and_speed(double output_rate_hz, const std::string& speed, JobOptions& job) {
  if (const auto problem = pipeline::check_output_rate(output_rate_hz)) {
    report(LogPriority::Error, *problem);
    return kExitUsage;
  }
  const auto factor = pipeline::parse_speed(speed);
  if (!factor) {
    report(LogPriority::Error, "--speed: '" + speed + "' is not max, realtime or a positive factor");
    return kExitUsage;
  }
  job.output_rate_hz = output_rate_hz;
  job.speed_factor = *factor;
  return kExitOk;
}

// Every file we write against every file we read or write: `replay X -o X` would truncate the
// recording before reading it.
std::optional<std::string> clobbered_file(const JobOptions& options) {
  const std::pair<const char*, const std::optional<std::string>*> outputs[] = {
      {"estimates output", &options.output}, {"recording", &options.record_path}, {"state file", &options.state_path}};
  for (std::size_t i = 0; i < std::size(outputs); ++i) {
    const auto& [what, path] = outputs[i];
    if (!*path || **path == "-") continue;
    for (const auto& input : options.input_paths)
      if (same_file(**path, input))
        return std::string("the ") + what + " " + **path + " is the input " + input +
               " itself: refusing to overwrite it";
    for (std::size_t j = i + 1; j < std::size(outputs); ++j) {
      const auto& [other, other_path] = outputs[j];
      if (*other_path && **other_path != "-" && same_file(**path, **other_path))
        return std::string("the ") + what + " and the " + other + " are one file (" + **path + ")";
    }
  }
  return std::nullopt;
}

int run_job(core::SampleSource& source, const JobOptions& options) {
  if (const auto clash = clobbered_file(options)) {
    report(LogPriority::Error, *clash);
    return kExitUsage;
  }
  // Start-up, in order. Each part is an object declared after the ones it needs, so leaving
  // this function takes them down in reverse; the pipeline finishes its sinks the same way.
  install_stop_signals();
  Notifier notifier;
  auto estimator = std::make_unique<core::Estimator>(options.settings);
  if (options.state_path) pipeline::restore_state(*estimator, *options.state_path, options.state_restore_heading);

  std::unique_ptr<DdsNode> node;
  if (options.publish) {
    try {
      DdsSettings dds = options.dds;
      if (dds.ros.hardware_id == RosSettings{}.hardware_id) dds.ros.hardware_id = source.describe();
      node = std::make_unique<DdsNode>(dds);
    } catch (const std::exception& error) {
      report(LogPriority::Error, std::string("DDS: ") + error.what());
      return kExitSoftware;
    }
    if (options.wait_subscribers_s > 0 && !node->wait_for_subscribers(options.wait_subscribers_s, &stop_flag()) &&
        !stop_requested()) {
      char waited[32];
      std::snprintf(waited, sizeof waited, "%.1f", options.wait_subscribers_s);
      report(LogPriority::Warning, std::string("no orientation subscriber within ") + waited + " s; publishing anyway");
    }
  }

  pipeline::PipelineOptions pipeline_options;
  pipeline_options.batch = options.batch;
  pipeline_options.duration_s = options.duration_s;
  pipeline_options.stop = &stop_flag();
  if (options.speed_factor > 0) pipeline_options.pacer.emplace(options.speed_factor, &stop_flag());
  pipeline::Pipeline pipeline(source, std::move(estimator), pipeline_options);

  std::optional<pipeline::RecordingSink> recording;
  std::optional<pipeline::RollingRecordingSink> rolling;
  std::optional<pipeline::EstimatesSink> estimates;
  pipeline::OutputDrops drops;
  std::optional<pipeline::ExpendableSink> recording_guard, estimates_guard;
  const bool expendable = options.files_expendable && node != nullptr;
  try {
    if (!options.rolling.dir.empty()) {
      rolling.emplace(options.rolling, options.record_comments, wall_now_s);
      if (expendable) rolling->resume_after_errors(drops);  // a lost file is followed by a new one
      pipeline.add_sink(*rolling);
    }
    if (options.record_path) {
      recording.emplace(*options.record_path, options.record_comments);
      pipeline.add_sink(expendable ? recording_guard.emplace(*recording, "recording", drops)
                                   : static_cast<pipeline::Sink&>(*recording));
    }
    if (options.output) {
      estimates.emplace(*options.output, options.output_rate_hz, source.nominal_rate_hz(),
                        options.settings.segments.segment_s);
      pipeline.add_sink(expendable ? estimates_guard.emplace(*estimates, "estimates output", drops)
                                   : static_cast<pipeline::Sink&>(*estimates));
    }
  } catch (const OutputError& error) {
    report(LogPriority::Error, std::string(error.what()));
    return kExitCantCreate;
  }
  std::optional<pipeline::DdsSink> dds;
  if (node) {
    const auto clock = source.health().live || options.speed_factor > 0 ? pipeline::StampClock::FirstSample
                                                                        : pipeline::StampClock::EachSample;
    pipeline.add_sink(dds.emplace(*node, source, clock, options.dds.on_duplicate));
    dds->watch_outputs(&drops);
    pipeline.set_inbox(&*dds);
  }
  std::optional<pipeline::StateSink> state;
  if (options.state_path) pipeline.add_sink(state.emplace(*options.state_path, options.state_save_interval_s));
  pipeline::ServiceSink service(notifier);
  pipeline.add_sink(service);
  std::optional<pipeline::ProgressSink> progress;
  if (options.progress && !options.quiet && pipeline::ProgressSink::wanted())
    pipeline.add_sink(progress.emplace(options.progress));
  pipeline.set_reloader([&options](const core::Estimator& running) { return reload(options, running); });

  const auto started = std::chrono::steady_clock::now();
  const pipeline::Outcome outcome = pipeline.run();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  // (A refusal was logged where it was decided.)
  if (!outcome.error.empty() && outcome.ending != pipeline::Ending::Refused) report(LogPriority::Error, outcome.error);
  if (outcome.ending == pipeline::Ending::BadInput)
    report(LogPriority::Error, "stopped there; estimates up to the previous sample are kept");
  if (drops.count > 0)
    report(LogPriority::Warning,
           std::to_string(drops.count) + " file output(s) dropped, the run went on publishing; last: " + drops.last);
  if (node) {
    // Late subscribers still get the latest GyroBias and Status (transient-local) meanwhile.
    linger(options.linger_s);
    if (!options.quiet) {
      const InboundCounts inbound = node->inbound();
      std::fprintf(stderr, "headingd %s: published %llu orientation messages; commands %llu accepted, %llu refused",
                   options.command.c_str(), static_cast<unsigned long long>(node->orientation_sent()),
                   static_cast<unsigned long long>(inbound.commands_accepted),
                   static_cast<unsigned long long>(inbound.commands_rejected));
      if (!options.dds.ros.stop_hint.topic.empty())
        std::fprintf(stderr, "; vehicle motion messages %llu accepted, %llu refused",
                     static_cast<unsigned long long>(inbound.motion_accepted),
                     static_cast<unsigned long long>(inbound.motion_refused));
      std::fprintf(stderr, "\n");
    }
    node.reset();  // deletes the participant: no shared-memory files left behind
  }
  if (!options.quiet && outcome.samples > 0) {
    Summary summary;
    summary.command = options.command;
    summary.ending = pipeline::ending_name(outcome.ending);
    summary.samples = outcome.samples;
    summary.first_t_s = outcome.first_t_s;
    summary.last_t_s = outcome.last_t_s;
    summary.wall_s = wall_s;
    if (estimates) {
      summary.output = estimates->path();
      summary.rows = estimates->rows_written();
    }
    if (recording) summary.recording = recording->path();
    if (rolling)
      summary.recording =
          (rolling->path().empty() ? options.rolling.dir + "/ (no file open at the end)" : rolling->path()) +
          " (the last of " + std::to_string(rolling->files_started()) + " started, " +
          (rolling->files_lost() > 0 ? std::to_string(rolling->files_lost()) + " lost to write errors, "
                                     : std::string()) +
          std::to_string(rolling->files_deleted()) + " old ones deleted)";
    print_summary(summary, source, pipeline.estimator());
  }
  if (outcome.estimator_fault && exit_code(outcome.ending) == kExitOk) {
    report(LogPriority::Error, "the estimator faulted (non-finite state); the heading after it is not valid");
    return kExitSoftware;
  }
  return exit_code(outcome.ending);
}

}  // namespace headingd::app
