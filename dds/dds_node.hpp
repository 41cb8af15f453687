#pragma once
// headingd on DDS (Fast DDS 2.9): one participant; writers for Orientation, the ROS 2 Imu,
// GyroBias and Status with QoS chosen on purpose (bias and status reliable + transient-local
// so a late subscriber gets the latest; orientation keep-last with a deadline, best-effort or
// reliable by config); a reader for HeadingCommand whose messages are validated before use.
// XML profiles named headingd_<topic> override the writers' QoS. Destroying the node deletes
// every entity and the participant, so no shared-memory files are left behind.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/diagnostics.hpp"
#include "core/estimate.hpp"
#include "dds/dds_settings.hpp"

namespace headingd::app {

// SensorState in the IDL, in its order.
enum class SensorState : int { Starting = 0, Ok = 1, Degraded = 2, Failed = 3, Replay = 4 };

struct StatusReport {
  SensorState state = SensorState::Starting;
  double sample_rate_hz = 0.0;
  std::uint64_t samples_received = 0, samples_dropped = 0, bus_errors = 0, fifo_overruns = 0;
  double uptime_s = 0.0;
  std::uint32_t other_publishers = 0;
};

// The most Orientation (and Imu) messages one wake-up of the sensor can make due at once, with
// margin: the best-effort writer keeps this many, and so should a reader that wants them all.
inline constexpr int kOrientationBurst = 8;

// Another participant publishing our orientation topic.
struct Rival {
  std::string guid_prefix;         // of its participant, as Fast DDS prints it
  std::string participant;         // its participant name ("headingd" for another instance)
  bool started_before_us = false;  // by the start times in the participants' user data
};

class DdsNode {
 public:
  // Throws std::runtime_error naming what could not be created.
  explicit DdsNode(const DdsSettings& settings);
  ~DdsNode();
  DdsNode(const DdsNode&) = delete;
  DdsNode& operator=(const DdsNode&) = delete;

  // Called for every estimate: true when a message is due by the estimate's time (then call
  // publish with the same estimate). Cheap, so the caller builds diagnostics only when needed.
  bool due(const core::Estimate& estimate);
  // Publishes what is due. `wall_offset_s` turns the estimate's clock into wall-clock time.
  void publish(const core::Estimate& estimate, const core::Diagnostics& diagnostics, const StatusReport& status,
               double wall_offset_s);
  // Appends the commands received and validated since the last call (rejected ones are
  // counted and logged).
  void take_commands(std::vector<ValidCommand>& out);
  std::uint64_t commands_accepted() const;
  std::uint64_t commands_rejected() const;
  std::uint64_t orientation_sent() const { return orientation_seq_; }
  // Other publishers of our orientation topic discovered since the last call.
  std::vector<Rival> take_rivals();
  // Waits up to `seconds` for a subscriber to match the orientation writer; true if one did.
  // A raised `stop` ends the wait at once (SIGTERM during discovery).
  bool wait_for_subscribers(double seconds, const std::atomic<bool>* stop = nullptr);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  DdsSettings settings_;
  std::uint64_t orientation_seq_ = 0;
  double next_orientation_s_ = -1e300;
  double next_status_s_ = -1e300;
  double next_bias_s_ = -1e300;
  // The last segment verdict: a live reader cannot wait for the segment in progress, so
  // Orientation.still says what the estimator concluded last (a gate trip ends it at once).
  bool last_verdict_still_ = false;
};

}  // namespace headingd::app
