#pragma once
// headingd's native recording format, owned here: the reader (csv_replay) and the writers
// (run --record, record, simulate) take the column names from this one place.
//   # comment lines (provenance)
//   time_s,gx_dps,gy_dps,gz_dps,temp_c
// Columns are found by name on reading, so the order is ours to choose when writing.
#include <string>
#include <string_view>

#include "core/sample.hpp"
#include "io/csv_out.hpp"

namespace headingd::app {

inline constexpr std::string_view kNativeTimeColumn = "time_s";
inline constexpr std::string_view kNativeRateColumns[3] = {"gx_dps", "gy_dps", "gz_dps"};
inline constexpr std::string_view kNativeTempColumn = "temp_c";
// How the recorder's last line at the end of a run begins ("# measured output rate 378.800 Hz; …");
// a file split off mid-run ends "# continued in NAME" instead.
inline constexpr const char* kEndOfRunComment = "measured output rate";
// Each file of a rolling series names its run among the header's comments ("# rolling series run
// headingd-20261207T063107Z, file 3": the run's first file): `replay --join` tells runs apart by it
// where the files themselves cannot (a crash and a restart on the same boot, a lost file between).
inline constexpr const char* kSeriesRunComment = "rolling series run ";

// How many decimals the time and temperature get. The rates are written exactly (the shortest
// text of the double), so a replay parses the very values that were recorded.
struct RecordingPrecision {
  int time_decimals = 9;  // the driver's nanoseconds
  int temp_decimals = 1;
};

class RecordingWriter {
 public:
  // `comments`: '#' lines, each ending in a newline (may be empty). Throws OutputError.
  RecordingWriter(const std::string& path, std::string_view comments, RecordingPrecision precision);
  void add(const core::Sample& sample);
  // A '#' line after the samples (e.g. the counters at the end of a recording).
  void comment(std::string_view line);
  void push() { out_.push(); }  // what was added is on disk (a .zst as complete blocks)
  void close();                 // flushes; throws OutputError
  const std::string& path() const { return out_.path(); }

 private:
  CsvOut out_;
  RecordingPrecision precision_;
};

}  // namespace headingd::app
