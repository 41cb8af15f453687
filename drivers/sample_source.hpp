#pragma once
// Every source of samples — the live chip, a recorded file, the simulator — looks the same
// to the pipeline (gpsd's gpsfake idea: replay goes the path live data takes).
#include <cstddef>
#include <span>
#include <string>

#include "core/sample.hpp"

namespace headingd::drivers {

class SampleSource {
 public:
  virtual ~SampleSource() = default;
  // Waits for samples and fills `out` from the front; returns how many. Zero means the
  // source has ended. Throws InputError on bad input, after returning every good sample
  // that came before it.
  virtual std::size_t read(std::span<core::Sample> out) = 0;
  // Releases the underlying file or device; reading after close returns zero.
  virtual void close() = 0;
  // One line for logs and summaries: what this source is reading.
  virtual std::string describe() const = 0;
};

}  // namespace headingd::drivers
