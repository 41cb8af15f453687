#pragma once
// The persisted estimator state, like chrony's drift file: bias per axis with its sigma, the
// temperature it was measured at, and the temperature model's sums. Written atomically (temp
// file, fsync, rename, fsync of the directory) so that a crash at any moment leaves the old or
// the new file, never a broken one; read back with a checksum, so a corrupt, truncated or
// foreign file is reported and ignored.
#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/diagnostics.hpp"
#include "core/sample.hpp"
#include "core/temperature_model.hpp"

namespace headingd::app {

// What the estimator learned (core::LearnedState, its temperatures too), and when.
struct SavedState : core::LearnedState {
  double saved_unix_s = 0.0;
};

class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// For tests: the write stops (throws SimulatedCrash) right after step `crash_after` of
// 0 create temp, 1 write half, 2 write rest, 3 fsync, 4 close, 5 rename, 6 fsync directory.
struct SimulatedCrash {
  int step;
};

void save_state(const std::string& path, const SavedState& state, int crash_after = -1);
// Throws StateError naming the file and what is wrong with it.
SavedState load_state(const std::string& path);
std::string format_state(const SavedState& state);
// A state file's body (everything before its checksum line) with that line appended: what
// format_state ends with, for tools and the fuzzer that build or mutate a body by hand.
std::string seal_state(const std::string& body);
SavedState parse_state(const std::string& text, const std::string& name);

}  // namespace headingd::app
