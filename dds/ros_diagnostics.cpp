#include "dds/ros_diagnostics.hpp"

#include <cmath>
#include <cstdio>

#include "core/method.hpp"
#include "dds/stop_hint.hpp"

namespace headingd::app {
namespace {

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string vector(const core::Vec3& v) { return number(v.x()) + " " + number(v.y()) + " " + number(v.z()); }

// The node's name with its namespace, as diagnostic_updater prefixes its tasks: /diagnostics
// is one topic for the whole fleet.
std::string qualified_node(const RosSettings& ros) {
  return ros.node_namespace == "/" ? ros.node_name : ros.node_namespace.substr(1) + "/" + ros.node_name;
}

// The worse of the two wins; the message of the first at that level stays.
void raise(DiagnosticEntry& entry, DiagnosticLevel level, const std::string& message) {
  if (static_cast<int>(level) > static_cast<int>(entry.level)) {
    entry.level = level;
    entry.message = message;
  }
}

}  // namespace

std::vector<DiagnosticEntry> DiagnosticsBuilder::build(const core::Estimate& e, const core::Diagnostics& d,
                                                       const StatusReport& report, const InboundCounts& inbound) {
  return {sensor(e, report), estimator(e, d, inbound)};
}

DiagnosticEntry DiagnosticsBuilder::sensor(const core::Estimate& e, const StatusReport& r) {
  DiagnosticEntry entry;
  entry.name = qualified_node(ros_) + ": sensor";
  entry.hardware_id = ros_.hardware_id;
  entry.message = r.state == SensorState::Replay ? "replaying a recording" : sensor_state_name(r.state);
  const std::uint64_t faults = r.bus_errors + r.fifo_overruns + r.samples_dropped + r.recoveries;
  if (faults > faults_seen_) last_fault_t_s_ = e.t_s;
  const std::uint64_t new_faults = faults - std::min(faults, faults_seen_);
  faults_seen_ = faults;
  if (r.state == SensorState::Failed) raise(entry, DiagnosticLevel::Error, "sensor failed");
  const double rate = r.sample_rate_hz > 0 ? r.sample_rate_hz : r.nominal_rate_hz;
  if (rate > 0 && static_cast<double>(r.stuck_samples) >= kStuckS * rate)
    raise(entry, DiagnosticLevel::Error,
          "output stuck: " + std::to_string(r.stuck_samples) + " identical samples in a row");
  if (r.state == SensorState::Degraded) raise(entry, DiagnosticLevel::Warn, "recovering from a sensor fault");
  if (e.t_s - last_fault_t_s_ <= kRecentS)
    raise(entry, DiagnosticLevel::Warn,
          "bus errors, FIFO overruns or lost samples in the last 10 s" +
              (new_faults > 0 ? " (+" + std::to_string(new_faults) + " now)" : std::string()));
  if (r.nominal_rate_hz > 0 && r.sample_rate_hz > 0 &&
      std::abs(r.sample_rate_hz / r.nominal_rate_hz - 1.0) > kRateTolerance)
    raise(entry, DiagnosticLevel::Warn,
          "output rate " + number(r.sample_rate_hz) + " Hz, nominal " + number(r.nominal_rate_hz) + " Hz");
  // While an output is not writing: a dropped file for the rest of the run, whatever the sensor
  // does; a rolling recording until its next file works (months of WARN after a disk that was
  // full for an hour would teach the operators to ignore it; the count stays below).
  if (r.outputs_failing > 0)
    raise(entry, DiagnosticLevel::Warn, "a file output cannot be written: " + r.output_dropped);
  entry.values = {{"state", sensor_state_name(r.state)},
                  {"rate_hz", number(r.sample_rate_hz)},
                  {"nominal_rate_hz", number(r.nominal_rate_hz)},
                  {"samples", std::to_string(r.samples_received)},
                  {"samples_dropped", std::to_string(r.samples_dropped)},
                  {"bus_errors", std::to_string(r.bus_errors)},
                  {"fifo_overruns", std::to_string(r.fifo_overruns)},
                  {"recoveries", std::to_string(r.recoveries)},
                  {"stuck_samples", std::to_string(r.stuck_samples)},
                  {"temperature_c", number(e.temp_c)},
                  {"uptime_s", number(r.uptime_s)},
                  {"file_outputs_dropped", std::to_string(r.outputs_dropped)},
                  {"file_outputs_failing", std::to_string(r.outputs_failing)}};
  return entry;
}

DiagnosticEntry DiagnosticsBuilder::estimator(const core::Estimate& e, const core::Diagnostics& d,
                                              const InboundCounts& inbound) {
  DiagnosticEntry entry;
  entry.name = qualified_node(ros_) + ": estimator";
  entry.hardware_id = ros_.hardware_id;
  entry.message = "tracking the bias";
  const double sigma = e.heading_sigma_deg;
  const bool has_sigma = d.method == core::Method::Auto;
  if (e.fault) raise(entry, DiagnosticLevel::Error, "estimator fault: state not finite, heading frozen; restart");
  if (d.in_startup) raise(entry, DiagnosticLevel::Warn, "start-up: measuring the bias, keep the platform still");
  if (has_sigma && !std::isfinite(sigma)) raise(entry, DiagnosticLevel::Error, "heading sigma is not finite");
  // The start-up segment's held heading has the sigma of a turn it could hide until it is judged
  // (a start in a turn, or a chip far from zero): seconds that pass by themselves, already WARN,
  // and no heading to set yet.
  if (has_sigma && sigma > ros_.heading_sigma_error_deg && !d.in_startup)
    raise(entry, DiagnosticLevel::Error, "heading sigma " + number(sigma) + " deg: set the heading");
  if (has_sigma && sigma > ros_.heading_sigma_warn_deg)
    raise(entry, DiagnosticLevel::Warn, "heading sigma " + number(sigma) + " deg");
  const double still_age_s = std::isfinite(d.last_still_t_s) ? e.t_s - d.last_still_t_s : NAN;
  if (!d.in_startup && has_sigma && still_age_s > ros_.still_age_warn_s)
    raise(entry, DiagnosticLevel::Warn, "no still segment for " + number(still_age_s) + " s");
  if (d.hint_conflicts > conflicts_seen_) last_conflict_t_s_ = e.t_s;
  conflicts_seen_ = d.hint_conflicts;
  if (e.t_s - last_conflict_t_s_ <= kRecentS)
    raise(entry, DiagnosticLevel::Warn, "the vehicle says stopped but the gyro turns: the gyro wins");
  if (d.bias_recoveries > restarts_seen_) last_restart_t_s_ = e.t_s;
  restarts_seen_ = d.bias_recoveries;
  if (e.t_s - last_restart_t_s_ <= kRecentS)
    raise(entry, DiagnosticLevel::Warn, "the bias restarted from a quiet period it could not explain");
  if (d.returns_mended > returns_seen_) last_return_t_s_ = e.t_s;
  returns_seen_ = d.returns_mended;
  if (e.t_s - last_return_t_s_ <= kRecentS)
    raise(entry, DiagnosticLevel::Warn,
          "heading corrected by " + number(d.last_return_correction_deg) +
              " deg: a bias restart had returned to a level an earlier stop measured");
  std::string model;
  for (std::size_t a = 0; a < 3; ++a) model += std::string(a ? " " : "") + (d.temperature[a].ready ? "on" : "off");
  entry.values = {{"method", std::string(core::method_name(d.method))},
                  {"heading_deg", number(e.heading_deg)},
                  {"heading_sigma_deg", number(sigma)},
                  {"heading_fixes", std::to_string(d.heading_fixes)},
                  {"heading_fix_offset_deg", number(d.heading_fix_offset_deg)},
                  {"bias_dps", vector(e.bias_dps)},
                  {"bias_sigma_dps", vector(e.bias_sigma_dps)},
                  {"last_still_age_s", number(still_age_s)},
                  {"accepted_segments", std::to_string(d.accepted_segments)},
                  {"rejected_segments", std::to_string(d.rejected_segments)},
                  {"rejected_rate_changing", std::to_string(d.rate_changed_segments)},
                  {"bias_restarts", std::to_string(d.bias_recoveries)},
                  {"bias_restarts_taken_back", std::to_string(d.recoveries_taken_back)},
                  {"bias_restarts_refused", std::to_string(d.refused_recoveries)},
                  {"bias_restarts_of_saved_state", std::to_string(d.saved_bias_restarts)},
                  {"noise_of_saved_state_replaced", std::to_string(d.saved_noise_replaced)},
                  {"returns_mended", std::to_string(d.returns_mended)},
                  {"gaps_bridged", std::to_string(d.gaps_bridged)},
                  {"temperature_model", model},
                  {"temperature_models_refuted", std::to_string(d.refuted_models)},
                  {"motion_hint", hint_name(d.motion_hint)},
                  {"hint_conflicts", std::to_string(d.hint_conflicts)},
                  {"motion_messages_accepted", std::to_string(inbound.motion_accepted)},
                  {"motion_messages_refused", std::to_string(inbound.motion_refused)},
                  {"commands_accepted", std::to_string(inbound.commands_accepted)},
                  {"commands_rejected", std::to_string(inbound.commands_rejected)}};
  if (has_sigma) {
    entry.values.emplace_back("heading_variance_scale", number(d.heading_variance_scale));
    entry.values.emplace_back("sigma_stops_weighed", std::to_string(d.sigma_stops_weighed));
    entry.values.emplace_back("sigma_fixes_weighed", std::to_string(d.sigma_fixes_weighed));
  }
  // Learned from heading fixes only: absent until a fix after a turn has told it.
  if (!std::isnan(d.scale_z_sigma)) {
    entry.values.emplace_back("scale_z", number(d.scale_z));
    entry.values.emplace_back("scale_z_sigma", number(d.scale_z_sigma));
  }
  return entry;
}

}  // namespace headingd::app
