#include "pipeline/service_sink.hpp"

#include <cstdio>

#include "service/log.hpp"

namespace headingd::pipeline {
namespace {
constexpr auto kStatusEvery = std::chrono::seconds(10);

// Whether a counter rose since last seen (then it is seen): each event is logged once.
bool rose(std::uint64_t count, std::uint64_t& seen) {
  const bool risen = count > seen;
  seen = count;
  return risen;
}
}  // namespace

void ServiceSink::batch_done(const core::Estimator& estimator, const core::SampleSource& source) {
  const core::Estimate& last = estimator.last();
  const core::Diagnostics diagnostics = estimator.diagnostics();
  char text[300];
  if (rose(diagnostics.saved_noise_replaced, saved_noise_replaced_seen_)) {
    std::snprintf(text, sizeof text,
                  "the saved noise figures did not fit the first still segment (a changed rate or bandwidth, or "
                  "another sensor): sigma_still measured again, z now %.4f dps",
                  diagnostics.sigma_still_dps.z());
    app::log(app::LogPriority::Warning, "noise", text);
  }
  if (rose(diagnostics.saved_bias_restarts, saved_bias_restarts_seen_)) {
    recoveries_seen_ = diagnostics.bias_recoveries;  // this one, said here
    std::snprintf(text, sizeof text,
                  "the saved bias did not match the first still segment: the zero-rate level moved while headingd "
                  "was down (a power cycle, another sensor); the bias restarted there (z now %+.4f dps), and the "
                  "next stop decides if it was a slow turn instead",
                  last.bias_dps.z());
    app::log(app::LogPriority::Warning, "bias-recovery", text);
  }
  if (rose(diagnostics.trail_restarts, trail_restarts_seen_)) {
    recoveries_seen_ = diagnostics.bias_recoveries;  // this one, said here
    std::snprintf(text, sizeof text,
                  "the bias restarted on a line the rejected stops drew against temperature (%+.4f dps/C on z, a "
                  "drift faster than assumed without a model): the heading since the last accepted stop was mended "
                  "along it (sigma now %.1f deg) and the temperature model starts from it",
                  diagnostics.trail_slope_z_dps_per_c, last.heading_sigma_deg);
    app::log(app::LogPriority::Notice, "bias-recovery", text);
  }
  if (rose(diagnostics.bias_recoveries, recoveries_seen_)) {
    std::snprintf(text, sizeof text,
                  "the bias restarted from a long quiet period it could not explain (a start-up while turning, or "
                  "a wrong saved bias): heading sigma now %.1f deg; a heading fix (HeadingCommand set-heading) "
                  "restores it",
                  last.heading_sigma_deg);
    app::log(app::LogPriority::Warning, "bias-recovery", text);
  }
  if (rose(diagnostics.recoveries_taken_back, taken_back_seen_)) {
    std::snprintf(text, sizeof text,
                  "the bias restart was taken back: a stop agreed with the level before it (the quiet period was "
                  "a slow turn); heading sigma now %.1f deg",
                  last.heading_sigma_deg);
    app::log(app::LogPriority::Notice, "bias-recovery", text);
  }
  if (rose(diagnostics.returns_mended, returns_mended_seen_)) {
    std::snprintf(text, sizeof text,
                  "heading corrected by %+.1f deg: a bias restart had returned to a level an earlier stop measured, "
                  "and a stop after motion agreed (the bias had not moved; slow turns taken for stops had moved "
                  "the estimate); heading sigma now %.1f deg",
                  diagnostics.last_return_correction_deg, last.heading_sigma_deg);
    app::log(app::LogPriority::Notice, "bias-recovery", text);
  }
  if (rose(diagnostics.gaps_bridged, gaps_seen_)) {
    std::snprintf(text, sizeof text,
                  "a gap in the samples was bridged (%llu so far, %.2f s in all; lost samples, a chip set up "
                  "again?): the heading took the rate on either side, heading sigma now %.2f deg",
                  static_cast<unsigned long long>(diagnostics.gaps_bridged), diagnostics.gaps_bridged_s,
                  last.heading_sigma_deg);
    app::log(app::LogPriority::Warning, "sample-gap", text);
  }
  if (rose(diagnostics.refuted_models, refuted_models_seen_)) {
    std::snprintf(text, sizeof text,
                  "a temperature model was forgotten: a long quiet period's level followed the temperature with "
                  "another slope (%llu so far); the bias follows no model until stops teach it again",
                  static_cast<unsigned long long>(diagnostics.refuted_models));
    app::log(app::LogPriority::Notice, "temperature-model", text);
  }
  notifier_.ready();  // after the first good batch
  notifier_.sample_loop_alive();
  const auto now = std::chrono::steady_clock::now();
  if (now - last_status_ < kStatusEvery) return;
  last_status_ = now;
  const core::SourceHealth health = source.health();
  std::snprintf(text, sizeof text, "heading %.2f deg (sigma %.2f), bias z %+.4f dps, %llu samples, %llu bus errors",
                last.heading_deg, last.heading_sigma_deg, last.bias_dps.z(),
                static_cast<unsigned long long>(health.samples), static_cast<unsigned long long>(health.bus_errors));
  notifier_.status(text);
}

void ServiceSink::finish(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) {
  notifier_.stopping();
}

}  // namespace headingd::pipeline
