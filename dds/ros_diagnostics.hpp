#pragma once
// headingd's health as REP-107 diagnostics (diagnostic_msgs/DiagnosticArray on /diagnostics):
// one status for the sensor, one for the estimator, each with a level, a one-line message and
// its counters as key/values, named "<node>: sensor" and "<node>: estimator" as
// diagnostic_updater names its tasks. Plain values, no DDS: unit-testable.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.hpp"
#include "core/estimate.hpp"
#include "dds/ros_settings.hpp"
#include "dds/status_report.hpp"

namespace headingd::app {

enum class DiagnosticLevel : std::uint8_t { Ok = 0, Warn = 1, Error = 2, Stale = 3 };

struct DiagnosticEntry {
  DiagnosticLevel level = DiagnosticLevel::Ok;
  std::string name, message, hardware_id;
  std::vector<std::pair<std::string, std::string>> values;
};

// What the DDS node itself counts (commands and motion messages), beside the report.
struct InboundCounts {
  std::uint64_t commands_accepted = 0, commands_rejected = 0;
  std::uint64_t motion_accepted = 0, motion_refused = 0;
};

class DiagnosticsBuilder {
 public:
  explicit DiagnosticsBuilder(RosSettings ros) : ros_(std::move(ros)) {}
  // `t_s` is the estimate's clock: faults count as recent for kRecentS of it.
  std::vector<DiagnosticEntry> build(const core::Estimate& estimate, const core::Diagnostics& diagnostics,
                                     const StatusReport& report, const InboundCounts& inbound);

  static constexpr double kRecentS = 10.0;
  // Identical samples on all three axes for this long is a stuck output, not a quiet sensor:
  // noise changes at least one axis's least significant bit every few samples.
  static constexpr double kStuckS = 0.5;
  // Measured rate this far off the nominal (relative) is a fault: the datasheet's ODR is about
  // 5 % above what parts deliver, so allow more than that.
  static constexpr double kRateTolerance = 0.15;

 private:
  DiagnosticEntry sensor(const core::Estimate& estimate, const StatusReport& report);
  DiagnosticEntry estimator(const core::Estimate& estimate, const core::Diagnostics& diagnostics,
                            const InboundCounts& inbound);

  RosSettings ros_;
  std::uint64_t faults_seen_ = 0;  // bus errors + overruns + dropped + recoveries
  double last_fault_t_s_ = -1e300;
  std::uint64_t conflicts_seen_ = 0;
  double last_conflict_t_s_ = -1e300;
  // Bias restarts and returns mended: each moves the heading by up to tens of degrees at once,
  // which a consumer filtering the heading must hear about (WARN for kRecentS).
  std::uint64_t restarts_seen_ = 0, returns_seen_ = 0;
  double last_restart_t_s_ = -1e300, last_return_t_s_ = -1e300;
};

}  // namespace headingd::app
