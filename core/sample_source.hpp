#pragma once
// Every source of samples — the live chip, a recorded file, the simulator — looks the same
// to the pipeline (gpsd's gpsfake idea: replay goes the path live data takes).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "core/sample.hpp"

namespace headingd::core {

// How a source is doing, for status messages and summaries. A recording fills only what it
// knows (samples, rate); a sensor also counts its faults.
struct SourceHealth {
  bool live = false;     // a sensor, not a recording
  double rate_hz = 0.0;  // measured output rate; 0 until known
  std::uint64_t samples = 0, lost_samples = 0, bus_errors = 0, overruns = 0, recoveries = 0;
};

class SampleSource {
 public:
  virtual ~SampleSource() = default;
  // Waits for samples and fills `out` from the front; returns how many. Zero means the
  // source has ended. Throws InputError on bad input, after returning every good sample
  // that came before it; any other exception means the source is gone for good (a dead sensor).
  virtual std::size_t read(std::span<core::Sample> out) = 0;
  // The same as read(), without a copy where the source holds the samples already (in memory,
  // a read-ahead block): a view of at most `scratch.size()` samples, valid until the next call
  // to read() or next(); others fill `scratch` and view that.
  virtual std::span<const core::Sample> next(std::span<core::Sample> scratch) { return scratch.first(read(scratch)); }
  // Releases the underlying file or device; reading after close returns zero.
  virtual void close() = 0;
  // One line for logs and summaries: what this source is reading.
  virtual std::string describe() const = 0;
  virtual SourceHealth health() const = 0;
  // Every counter the source keeps, as one line for summaries; empty when it keeps none.
  virtual std::string counters_text() const { return {}; }
  // The rate the source is set up for, Hz; 0 when it cannot know before reading (a file).
  virtual double nominal_rate_hz() const { return 0.0; }
};

}  // namespace headingd::core
