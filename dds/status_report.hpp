#pragma once
// How the sensor and the run are doing, as the pipeline sees them: for Status and /diagnostics.
#include <cstdint>
#include <string>

namespace headingd::app {

// SensorState in the IDL, in its order.
enum class SensorState : int { Starting = 0, Ok = 1, Degraded = 2, Failed = 3, Replay = 4 };

// The one name of each state, for `echo`, /diagnostics and logs.
inline const char* sensor_state_name(SensorState state) {
  switch (state) {
    case SensorState::Starting:
      return "starting";
    case SensorState::Ok:
      return "ok";
    case SensorState::Degraded:
      return "degraded";
    case SensorState::Failed:
      return "failed";
    case SensorState::Replay:
      return "replay";
  }
  return "unknown";
}

struct StatusReport {
  SensorState state = SensorState::Starting;
  double sample_rate_hz = 0.0;   // measured
  double nominal_rate_hz = 0.0;  // what the sensor is set up for; 0 for a recording
  std::uint64_t samples_received = 0, samples_dropped = 0, bus_errors = 0, fifo_overruns = 0, recoveries = 0;
  std::uint64_t stuck_samples = 0;  // the current run of samples identical on all three axes
  double uptime_s = 0.0;
  std::uint32_t other_publishers = 0;
  std::uint64_t outputs_dropped = 0;  // file outputs the run went on without (a full disk)
  std::string output_dropped;         // which, and why: the last one
  std::uint64_t outputs_failing = 0;  // of them, not writing now (a rolling series that resumed is not)
};

}  // namespace headingd::app
