#include "app/batch_replay.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <thread>
#include <tuple>

#include "io/companion_file.hpp"
#include "io/csv_out.hpp"
#include "io/input_error.hpp"
#include "io/joined_replay.hpp"
#include "io/line_reader.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"
#include "service/signals.hpp"

namespace headingd::app {
namespace {

namespace fs = std::filesystem;

bool is_recording_name(const std::string& name) {
  for (const char* ending : {".csv", ".csv.zst", ".csv.gz"}) {
    const std::string e = ending;
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0 &&
        name.find(".estimates.") == std::string::npos)
      return true;
  }
  return false;
}

// One RFC 4180 field: quoted, quotes doubled, so a name with a comma or a newline stays one field.
std::string quoted(const std::string& text) {
  std::string field = "\"";
  for (const char c : text) field += c == '"' ? std::string("\"\"") : std::string(1, c);
  return field + "\"";
}

std::string number(double value, const char* format) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// The bias z over the run, from the first accepted still segment on (before it, it is the start value).
class BiasRange final : public pipeline::BatchSink {
 public:
  void batch_done(const core::Estimator& estimator, const core::SampleSource& /*source*/) override {
    if (estimator.diagnostics().accepted_segments == 0) return;
    const double z = estimator.last().bias_dps.z();
    low = std::min(low, z);
    high = std::max(high, z);
  }
  double low = std::numeric_limits<double>::infinity(), high = -std::numeric_limits<double>::infinity();
};

struct Row {
  std::string file, output;
  double hours = 0.0;
  std::uint64_t samples = 0, still = 0;
  double sigma_deg = std::nan(""), bias_z = std::nan(""), bias_low = std::nan(""), bias_high = std::nan("");
  std::string warnings;
  int code = kExitOk;
};

// The row's name: the recording, or for a folder joined the folder and how many.
std::string label_of(const std::vector<FoundRecording>& group) {
  if (group.size() == 1) return group.front().path;
  return fs::path(group.front().path).parent_path().string() + "/ (" + std::to_string(group.size()) + " joined)";
}

// One run of the source (a recording, or a folder's joined) through an estimator of its own.
Row replay_run(drivers::JoinedReplaySource& source, Row row, const BatchOptions& options) {
  try {
    pipeline::PipelineOptions pipeline_options;
    pipeline_options.batch = 4096;
    pipeline_options.stop = &stop_flag();
    pipeline::Pipeline line(source, std::make_unique<core::Estimator>(options.settings), pipeline_options);
    pipeline::EstimatesSink estimates(row.output, options.output_rate_hz, 0.0, options.settings.segments.segment_s);
    BiasRange range;
    line.add_sink(estimates);
    line.add_sink(range);
    const pipeline::Outcome outcome = line.run();
    const core::Diagnostics d = line.estimator().diagnostics();
    row.samples = outcome.samples;
    row.hours = (outcome.last_t_s - outcome.first_t_s) / 3600.0;
    row.still = d.accepted_segments;
    row.sigma_deg = line.estimator().last().heading_sigma_deg;
    row.bias_z = line.estimator().last().bias_dps.z();
    if (std::isfinite(range.low)) row.bias_low = range.low, row.bias_high = range.high;
    std::vector<std::string> notes;
    if (outcome.ending != pipeline::Ending::EndOfInput)
      notes.push_back(outcome.error.empty() ? pipeline::ending_name(outcome.ending) : outcome.error);
    if (d.accepted_segments == 0) notes.push_back("no still segment: bias never measured");
    if (d.bias_recoveries > 0) {
      std::string note = std::to_string(d.bias_recoveries) + " bias recoveries";
      if (d.recoveries_taken_back > 0) note += " (" + std::to_string(d.recoveries_taken_back) + " taken back)";
      if (d.returns_mended > 0) note += " (" + std::to_string(d.returns_mended) + " back to an earlier level)";
      notes.push_back(note);
    }
    if (d.gaps_bridged > 0)  // a fleet's recorder that loses samples shows in the table, not only in each log
      notes.push_back(std::to_string(d.gaps_bridged) + " gaps in the samples bridged");
    if (outcome.estimator_fault) notes.push_back("estimator fault");
    for (const auto& part : source.damaged_parts()) notes.push_back("damaged part passed: " + part.error);
    for (const auto& n : notes) row.warnings += (row.warnings.empty() ? "" : "; ") + n;
    if (outcome.ending == pipeline::Ending::BadInput || !source.damaged_parts().empty()) row.code = kExitDataError;
    if (outcome.ending == pipeline::Ending::OutputFailed) row.code = kExitCantCreate;
  } catch (const OutputError& error) {
    row.warnings = error.what();
    row.code = kExitCantCreate;
  }
  return row;
}

// A recording, or a folder joined: a row per run of the recorder in it (with --join a folder's
// series splits where a run ended: a restart, a reboot), each with its own estimates file named
// after the run's first recording.
std::vector<Row> replay_group(const std::vector<FoundRecording>& group, const BatchOptions& options) {
  Row first;
  first.file = label_of(group);
  first.output = estimates_path_for(group.front(), options.output_dir);
  std::vector<std::string> paths;
  paths.reserve(group.size());
  for (const auto& f : group) paths.push_back(f.path);
  std::vector<Row> rows;
  try {
    drivers::JoinedReplaySource source(paths, options.join);
    rows.push_back(replay_run(source, first, options));
    std::vector<std::string> run_starts{group.front().path};
    while (!stop_flag().load() && source.next_run()) {
      const auto start = std::find_if(group.begin(), group.end(),
                                      [&](const FoundRecording& f) { return f.path == source.current_file(); });
      Row next;
      next.output = estimates_path_for(*start, options.output_dir);
      run_starts.push_back(start->path);
      rows.push_back(replay_run(source, next, options));
    }
    if (rows.size() > 1)
      for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].file = fs::path(run_starts[i]).parent_path().string() + "/ run " + std::to_string(i + 1) + " from " +
                       fs::path(run_starts[i]).filename().string();
  } catch (const drivers::OpenError& error) {
    first.warnings = error.what();
    first.code = kExitNoInput;
    rows = {first};
  } catch (const drivers::InputError& error) {
    first.warnings = error.what();
    first.code = kExitDataError;
    rows = {first};
  }
  return rows;
}

}  // namespace

namespace {

// A series' files by their run and number; any other file by its own name, as the first of a
// run of its own (a series' first file's name, without the ending, is its run's name).
void put_in_series_order(std::vector<FoundRecording>& found) {
  struct Keyed {
    std::string folder, run;
    long file;
    FoundRecording recording;
  };
  std::vector<Keyed> keyed;
  for (auto& f : found) {
    const fs::path path(f.path);
    const auto position = drivers::series_position(f.path);
    std::string stem = path.filename().string();
    stem = stem.substr(0, stem.find('.'));
    keyed.push_back(
        {path.parent_path().string(), position ? position->run : stem, position ? position->file : 0, std::move(f)});
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return std::tie(a.folder, a.run, a.file, a.recording.path) < std::tie(b.folder, b.run, b.file, b.recording.path);
  });
  for (std::size_t i = 0; i < found.size(); ++i) found[i] = std::move(keyed[i].recording);
}

// One directory's recordings, sorted; false after saying why when it cannot be read.
bool list_directory(const std::string& input, bool recursive, bool series_order, std::vector<FoundRecording>& files) {
  std::vector<FoundRecording> found;
  std::vector<std::string> skipped;
  std::error_code error;
  const auto take = [&](const fs::directory_entry& entry) {
    // A link counts even when it leads nowhere: its row then says so, and the exit code with it,
    // where skipping it would have left a vehicle out of the table without a word.
    std::error_code kind_error;
    const bool file_or_link = entry.is_regular_file(kind_error) || entry.is_symlink(kind_error);
    if (!file_or_link || !is_recording_name(entry.path().filename().string())) return;
    const std::string relative = entry.path().lexically_relative(input).string();
    // A simulation's truth.csv beside its imu.csv, a batch table written into the fleet's
    // directory: not recordings, left out and named (a file named on the command line is not).
    if (const auto kind = drivers::companion_kind(entry.path().string())) {
      skipped.push_back(drivers::printable(relative, 200) + " (" + *kind + ")");
      return;
    }
    found.push_back({entry.path().string(), entry.path().lexically_relative(input).parent_path().string()});
  };
  if (recursive) {
    fs::recursive_directory_iterator it(input, error), end;
    for (; !error && it != end; it.increment(error)) take(*it);
  } else {
    fs::directory_iterator it(input, error), end;
    for (; !error && it != end; it.increment(error)) take(*it);
  }
  if (error) {
    std::fprintf(stderr, "headingd: cannot list %s: %s\n", drivers::printable(input, 200).c_str(),
                 error.message().c_str());
    return false;
  }
  if (!skipped.empty()) {
    std::sort(skipped.begin(), skipped.end());
    std::string names;
    for (const auto& name : skipped) names += (names.empty() ? "" : ", ") + name;
    std::fprintf(stderr, "headingd: %s: left out, not recordings: %s\n", drivers::printable(input, 200).c_str(),
                 names.c_str());
  }
  if (found.empty()) {
    std::fprintf(stderr, "headingd: no recordings (*.csv, *.csv.zst, *.csv.gz) in %s%s\n",
                 drivers::printable(input, 200).c_str(), recursive ? " or below it" : "");
    return false;
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  if (series_order) put_in_series_order(found);
  files.insert(files.end(), found.begin(), found.end());
  return true;
}

}  // namespace

std::vector<FoundRecording> expand_inputs(const std::vector<std::string>& inputs, bool recursive, bool series_order) {
  std::vector<FoundRecording> files;
  for (const auto& input : inputs) {
    std::error_code error;
    if (fs::is_directory(input, error)) {
      if (!list_directory(input, recursive, series_order, files)) return {};
    } else if (fs::exists(input, error)) {
      files.push_back({input, ""});
    } else {
      std::fprintf(stderr, "headingd: cannot open %s: No such file or directory\n", input.c_str());
      return {};
    }
  }
  return files;
}

std::string estimates_path_for(const FoundRecording& input, const std::optional<std::string>& output_dir) {
  const fs::path path(input.path);
  std::string name = path.filename().string();
  for (const char* ending : {".zst", ".gz", ".csv"}) {
    const std::string e = ending;
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0)
      name.resize(name.size() - e.size());
  }
  const fs::path dir = output_dir ? fs::path(*output_dir) / input.under : path.parent_path();
  return (dir / (name + ".estimates.csv")).string();
}

int batch_settings(const std::optional<std::string>& config_path, const std::optional<std::string>& method,
                   core::EstimatorSettings& settings) {
  try {
    if (config_path) settings = load_config(*config_path).estimator;
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitConfig;
  }
  return apply_method_option(method, settings) ? 0 : kExitUsage;
}

std::vector<std::vector<FoundRecording>> group_by_folder(const std::vector<FoundRecording>& files) {
  std::vector<std::vector<FoundRecording>> groups;
  std::map<std::string, std::size_t> index;
  for (const auto& f : files) {
    const std::string folder = fs::path(f.path).parent_path().lexically_normal().string();
    const auto [it, fresh] = index.emplace(folder, groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(f);
  }
  return groups;
}

int run_batch_replay(const BatchOptions& options) {
  const std::vector<FoundRecording> files =
      options.found.empty() ? expand_inputs(options.inputs, options.recursive) : options.found;
  if (files.empty()) {
    if (!options.inputs.empty()) return kExitNoInput;
    std::fprintf(stderr, "headingd: replay: no recordings\n");
    return kExitNoInput;
  }
  std::vector<std::vector<FoundRecording>> groups;
  if (options.join)
    groups = group_by_folder(files);
  else
    for (const auto& f : files) groups.push_back({f});
  // Two recordings writing one estimates file would be a silent loss: refuse before starting.
  std::map<std::string, std::string> outputs;
  for (const auto& group : groups) {
    const std::string out = estimates_path_for(group.front(), options.output_dir);
    if (const auto [it, fresh] = outputs.emplace(out, group.front().path); !fresh) {
      std::fprintf(stderr, "headingd: %s and %s would both write %s; give distinct names or no --output-dir\n",
                   it->second.c_str(), group.front().path.c_str(), out.c_str());
      return kExitUsage;
    }
  }
  if (options.output_dir) {
    for (const auto& [out, file] : outputs) {  // the output directory, and the folders below it
      std::error_code error;
      const fs::path dir = fs::path(out).parent_path();
      fs::create_directories(dir, error);
      if (error) {
        std::fprintf(stderr, "headingd: cannot create %s: %s\n", dir.c_str(), error.message().c_str());
        return kExitCantCreate;
      }
    }
  }
  install_stop_signals();
  std::vector<std::vector<Row>> group_rows(groups.size());
  for (std::size_t i = 0; i < groups.size(); ++i) {  // what a signal leaves undone says so
    group_rows[i].resize(1);
    group_rows[i][0].file = label_of(groups[i]);
    group_rows[i][0].warnings = "not replayed: stopped by a signal";
  }
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < groups.size() && !stop_flag().load(); i = next++)
      group_rows[i] = replay_group(groups[i], options);
  };
  std::vector<std::thread> workers;
  const unsigned jobs = std::clamp<unsigned>(options.jobs, 1, static_cast<unsigned>(groups.size()));
  for (unsigned j = 1; j < jobs; ++j) workers.emplace_back(work);
  work();
  for (auto& w : workers) w.join();
  std::vector<Row> rows;
  for (auto& g : group_rows) rows.insert(rows.end(), g.begin(), g.end());

  // The file column as wide as its longest name (a run's row names its folder and first file), so
  // the figures stay in columns for a reader; scripts split on blanks or read --summary-csv.
  int width = 40;
  for (const auto& r : rows) width = std::max(width, static_cast<int>(drivers::printable(r.file, 200).size()));
  std::printf("%-*s %8s %10s %6s %9s %10s %21s  %s\n", width, "file", "hours", "samples", "still", "sigma_deg",
              "bias_z_dps", "bias_z_range_dps", "warnings");
  int code = kExitOk;
  for (const auto& r : rows) {
    std::printf("%-*s %8s %10llu %6llu %9s %10s %21s  %s\n", width, drivers::printable(r.file, 200).c_str(),
                number(r.hours, "%.3f").c_str(), static_cast<unsigned long long>(r.samples),
                static_cast<unsigned long long>(r.still), number(r.sigma_deg, "%.3f").c_str(),
                number(r.bias_z, "%+.4f").c_str(),
                (number(r.bias_low, "%+.4f") + ".." + number(r.bias_high, "%+.4f")).c_str(),
                r.warnings.empty() ? "-" : drivers::printable(r.warnings, 300).c_str());
    if (code == kExitOk && r.code != kExitOk) code = r.code;
  }
  std::fflush(stdout);
  if (options.summary_csv) {
    try {
      CsvOut csv(*options.summary_csv);
      csv.line(
          "file,estimates,hours,samples,still_segments,heading_sigma_deg,bias_z_dps,bias_z_min_dps,bias_z_max_dps,"
          "warnings");
      for (const auto& r : rows) {
        csv.text(quoted(r.file)).text(quoted(r.output)).number(r.hours, 6);
        csv.integer(static_cast<std::int64_t>(r.samples));
        csv.integer(static_cast<std::int64_t>(r.still)).number(r.sigma_deg, 6).number(r.bias_z, 6);
        csv.number(r.bias_low, 6).number(r.bias_high, 6).text(quoted(r.warnings));
        csv.end_line();
      }
      csv.close();
    } catch (const OutputError& error) {
      std::fprintf(stderr, "headingd: %s\n", error.what());
      return kExitCantCreate;
    }
  }
  return code;
}

}  // namespace headingd::app
