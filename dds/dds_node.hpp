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
#include "dds/imu_message.hpp"
#include "dds/ros_diagnostics.hpp"
#include "dds/status_report.hpp"

namespace headingd::app {

// The most Orientation (and Imu) messages one wake-up of the sensor can make due at once, with
// margin: the best-effort writer keeps this many, and so should a reader that wants them all.
inline constexpr int kOrientationBurst = 8;

// An inbound message refused, and why (for the caller's rate-limited log).
enum class RefusalKind { Command, Motion };
struct Refusal {
  RefusalKind kind;
  std::string why;
};

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
  // counted), and a motion hint whenever the vehicle's own motion topic changes its say.
  void take_commands(std::vector<ValidCommand>& out);
  // Appends why messages were refused since the last call (at most a few dozen are kept);
  // returns how many more were refused beyond those.
  std::uint64_t take_refusals(std::vector<Refusal>& out);
  InboundCounts inbound() const;
  std::uint64_t commands_accepted() const;
  std::uint64_t commands_rejected() const;
  std::uint64_t orientation_sent() const { return orientation_seq_; }
  // The sample time (not the stamp) that the last Orientation carried.
  double orientation_sample_t_s() const { return orientation_sample_t_s_; }
  double orientation_period_s() const { return 1.0 / settings_.orientation_rate_hz; }
  // Other publishers of our orientation topic discovered since the last call.
  std::vector<Rival> take_rivals();
  // Waits up to `seconds` for a subscriber to match the orientation writer; true if one did.
  // A raised `stop` ends the wait at once (SIGTERM during discovery).
  bool wait_for_subscribers(double seconds, const std::atomic<bool>* stop = nullptr);

  struct Impl;

 private:
  void publish_ros_health(const core::Estimate& e, const core::Diagnostics& diagnostics, const StatusReport& report,
                          const InboundCounts& counts, double stamp_s);

  std::unique_ptr<Impl> impl_;
  DdsSettings settings_;
  DiagnosticsBuilder diagnostics_builder_;
  RateWindow rates_;  // bias-corrected rates since the last Imu
  std::uint64_t orientation_seq_ = 0;
  double orientation_sample_t_s_ = 0.0;
  double next_orientation_s_ = -1e300;
  double next_status_s_ = -1e300;
  double next_bias_s_ = -1e300;
  // The last segment verdict: a live reader cannot wait for the segment in progress, so
  // Orientation.still says what the estimator concluded last (a gate trip ends it at once).
  bool last_verdict_still_ = false;
};

}  // namespace headingd::app
