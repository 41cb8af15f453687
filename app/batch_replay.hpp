#pragma once
// `replay A.csv B.csv.zst DIR/ --jobs N`: many recordings, each on its own (its own estimator,
// its own estimates file), in parallel, and one summary table at the end — a fleet's logs
// re-processed in one command.
#include <optional>
#include <string>
#include <vector>

#include "core/estimator.hpp"

namespace headingd::app {

// A recording to replay, and the folders between the directory named and it ("" for a file named,
// or one found at the directory's top): with --output-dir its estimates go there, below it.
struct FoundRecording {
  std::string path;
  std::string under;
};

struct BatchOptions {
  std::vector<std::string> inputs;  // files, or directories (their *.csv, *.csv.zst, *.csv.gz)
  bool recursive = false;           // directories read at every depth, not one level
  unsigned jobs = 1;
  std::optional<std::string> output_dir;   // estimates go here (below it, the path under a directory
                                           // named); default: beside each recording
  std::optional<std::string> summary_csv;  // the table as CSV too
  core::EstimatorSettings settings = core::kDefaultEstimatorSettings;
  double output_rate_hz = 10.0;
  // Each folder's recordings joined into one run, in name order (a vehicle's rolling series): one
  // row per folder, its estimates named after its first file (drivers::JoinedReplaySource).
  bool join = false;
  std::vector<FoundRecording> found;  // already expanded (then `inputs` is not read again)
};

// The recordings `inputs` names, in order, directories expanded (sorted; at every depth when
// `recursive`, links to directories not followed); empty after saying why on stderr when one
// is missing or unreadable. `series_order` (--join): a directory's files of a rolling series in
// the order their headers give (run, then number in the run), not their names' (a wall clock
// stepped back mid-run names later files earlier); the others by name, folder by folder.
std::vector<FoundRecording> expand_inputs(const std::vector<std::string>& inputs, bool recursive = false,
                                          bool series_order = false);

// The recordings grouped by the folder they are in, each group in the order found (folders in
// the order their first recording came): what `--join` replays as one run each.
std::vector<std::vector<FoundRecording>> group_by_folder(const std::vector<FoundRecording>& files);

// Where a recording's estimates go: <dir>/<name without .zst/.gz/.csv>.estimates.csv, dir being
// the recording's own, or the output directory with the recording's `under` below it.
std::string estimates_path_for(const FoundRecording& input, const std::optional<std::string>& output_dir);

// The estimator settings from --config and --method; 0, or the exit code after saying why.
int batch_settings(const std::optional<std::string>& config_path, const std::optional<std::string>& method,
                   core::EstimatorSettings& settings);

// Replays them all; prints the table on stdout. Exit 0 when every replay ended well, else the
// first failure's code (every recording is still replayed).
int run_batch_replay(const BatchOptions& options);

}  // namespace headingd::app
