#pragma once
// The summary on stderr at the end of run, replay and record: what was read, what the
// estimator concluded, where the estimates went, and for a sensor its counters.
#include <cstdint>
#include <optional>
#include <string>

#include "core/estimator.hpp"
#include "core/sample_source.hpp"

namespace headingd::app {

struct Summary {
  std::string command;  // run, replay, record
  std::string ending;   // "end of input", "stopped by signal", ...
  std::uint64_t samples = 0;
  double first_t_s = 0.0;
  double last_t_s = 0.0;
  double wall_s = 0.0;
  std::optional<std::string> output;  // estimates CSV
  std::uint64_t rows = 0;
  std::optional<std::string> recording;
};

void print_summary(const Summary& summary, const core::SampleSource& source, const core::Estimator& estimator);

}  // namespace headingd::app
