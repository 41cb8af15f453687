#include "pipeline/dds_sink.hpp"

#include <algorithm>
#include <utility>

#include "dds/dds_participant.hpp"
#include "service/log.hpp"

namespace headingd::pipeline {
namespace {
// After a sensor recovery, Status says DEGRADED this long (sample time).
constexpr double kDegradedAfterRecoveryS = 5.0;
}  // namespace

DdsSink::DdsSink(app::DdsNode& node, const core::SampleSource& source, StampClock clock,
                 app::DuplicatePolicy on_duplicate, WallStamps::WallClock wall)
    : node_(node),
      source_(source),
      clock_(clock),
      on_duplicate_(on_duplicate),
      stamps_(wall),
      wall_(std::move(wall)),
      newest_of_wakeup_(source.health().live) {}

void DdsSink::log_inbound(const core::Estimator& estimator) {
  refusals_.clear();
  const std::uint64_t more = node_.take_refusals(refusals_);
  // Through the log's per-kind limit (a few lines per 10 s) and its level: a flood of bad
  // messages is counted on Status and /diagnostics, not written line by line.
  for (const app::Refusal& refusal : refusals_) {
    const bool command = refusal.kind == app::RefusalKind::Command;
    app::log(app::LogPriority::Warning, command ? "refused command" : "refused motion",
             std::string(command ? "HeadingCommand" : "vehicle motion message") + " refused: " + refusal.why);
  }
  if (more > 0)
    app::log(app::LogPriority::Warning, "refused flood",
             std::to_string(more) + " more inbound messages refused (counted on Status)");
  if (const auto* automatic = estimator.automatic(); automatic != nullptr && automatic->hint_conflicts() > conflicts_) {
    conflicts_ = automatic->hint_conflicts();
    app::log(app::LogPriority::Warning, "hint conflict",
             "the vehicle says it stands still but the gyro turns: segment not taken as still (" +
                 std::to_string(conflicts_) + " so far)");
  }
}

void DdsSink::batch_done(const core::Estimator& estimator, const core::SampleSource& /*source*/) {
  if (publication_due_) {
    publication_due_ = false;
    const core::Estimate& newest = estimator.last();
    node_.publish(newest, estimator.diagnostics(), report(newest), wall_offset_s_);
  }
  log_inbound(estimator);
  for (const app::Rival& rival : node_.take_rivals()) {
    ++rivals_;
    const bool refuse = on_duplicate_ == app::DuplicatePolicy::Refuse && rival.started_before_us;
    const std::string text = "another publisher of our topics on this domain and prefix: participant '" +
                             rival.participant + "', GUID prefix " + rival.guid_prefix + ", started " +
                             (rival.started_before_us ? "before" : "after") +
                             " this one; subscribers get both streams interleaved (give each instance its own "
                             "[dds] prefix or domain_id)" +
                             (refuse ? "; on_duplicate = refuse: this one stops" : "");
    app::log(app::LogPriority::Error, "duplicate " + rival.guid_prefix, text);
    if (refuse) throw RunRefused(text);
  }
}

app::StatusReport DdsSink::report(const core::Estimate& estimate) {
  const core::SourceHealth health = source_.health();
  if (health.recoveries > recoveries_seen_) {
    recoveries_seen_ = health.recoveries;
    degraded_until_s_ = estimate.t_s + kDegradedAfterRecoveryS;
  }
  app::StatusReport r;
  if (estimate.fault)
    r.state = app::SensorState::Failed;
  else if (!health.live)
    r.state = app::SensorState::Replay;
  else if (estimate.t_s < degraded_until_s_)
    r.state = app::SensorState::Degraded;
  else
    r.state = estimate.in_startup ? app::SensorState::Starting : app::SensorState::Ok;
  const double span_s = estimate.t_s - first_t_s_;
  r.sample_rate_hz = health.rate_hz > 0 ? health.rate_hz
                     : span_s > 0       ? static_cast<double>(samples_ - 1) / span_s
                                        : 0.0;
  r.samples_received = samples_;
  r.samples_dropped = health.lost_samples;
  r.bus_errors = health.bus_errors;
  r.fifo_overruns = health.overruns;
  r.recoveries = health.recoveries;
  r.nominal_rate_hz = source_.nominal_rate_hz();
  r.stuck_samples = stuck_samples_;
  r.uptime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  r.other_publishers = rivals_;
  if (drops_ != nullptr) {
    r.outputs_dropped = drops_->count;
    r.output_dropped = drops_->last;
    r.outputs_failing = drops_->failing;
  }
  return r;
}

void DdsSink::add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) {
  if (samples_++ == 0) first_t_s_ = sample.t_s;
  stuck_samples_ = samples_ > 1 && sample.rate_dps == last_rate_dps_ ? stuck_samples_ + 1 : 0;
  last_rate_dps_ = sample.rate_dps;
  // Stamps never go backwards, whatever the system clock does meanwhile.
  const double stamp_s =
      clock_ == StampClock::FirstSample ? stamps_.stamp(sample.t_s) : std::max(wall_(), last_stamp_s_);
  last_stamp_s_ = stamp_s;
  if (newest_of_wakeup_ && publication_due_ && estimate.t_s >= due_since_t_s_ + node_.orientation_period_s()) {
    // A second publication time within one wake-up (a wake-up longer than the publication
    // period): the pending one goes out now with the sample before this one, so the rate holds
    // and no two messages carry the same sample; this sample starts the next.
    publication_due_ = false;
    node_.publish(previous_, estimator.diagnostics(), report(previous_), previous_wall_offset_s_);
  }
  wall_offset_s_ = stamp_s - sample.t_s;
  const bool due = node_.due(estimate);
  if (newest_of_wakeup_) {
    previous_ = estimate;
    previous_wall_offset_s_ = wall_offset_s_;
    // Due stays true until a publication: the samples after the first due one are the same
    // publication time, to go out at the end of the wake-up with the newest sample.
    if (due && !publication_due_) {
      publication_due_ = true;
      due_since_t_s_ = estimate.t_s;
    }
    return;
  }
  if (!due) return;
  node_.publish(estimate, estimator.diagnostics(), report(estimate), wall_offset_s_);
}

}  // namespace headingd::pipeline
