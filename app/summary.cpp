#include "app/summary.hpp"

#include <array>
#include <cstdio>

namespace headingd::app {
namespace {

void print_estimator(const core::Estimator& estimator) {
  const core::Diagnostics d = estimator.diagnostics();
  std::fprintf(stderr, "  method       %s; segments up to %.1f s: %llu accepted as still, %llu rejected\n",
               std::string(core::method_name(d.method)).c_str(), d.segment_s,
               static_cast<unsigned long long>(d.accepted_segments),
               static_cast<unsigned long long>(d.rejected_segments));
  const core::Vec3& sigma = d.sigma_still_dps;
  std::fprintf(stderr, "  sigma_still  x %.4f  y %.4f  z %.4f dps\n", sigma.x(), sigma.y(), sigma.z());
  if (d.method == core::Method::Auto) {
    const core::Vec3& n = d.noise_density_dps_rt_hz;
    std::fprintf(stderr, "  noise        x %.4f  y %.4f  z %.4f dps/sqrt(Hz) (angle random walk)\n", n.x(), n.y(),
                 n.z());
    std::fprintf(stderr, "  creep        %llu accepted segments taken back when the next one showed a creep\n",
                 static_cast<unsigned long long>(d.retracted_segments));
    if (d.rate_changed_segments > 0)
      std::fprintf(stderr,
                   "  changing     %llu segments that passed the mean test rejected because the rate changed within "
                   "them (motion starting or stopping)\n",
                   static_cast<unsigned long long>(d.rate_changed_segments));
    if (d.bias_recoveries > 0)
      std::fprintf(stderr,
                   "  recovered    the bias started again %llu times from a long quiet period it could not "
                   "explain (a start-up while turning?)\n",
                   static_cast<unsigned long long>(d.bias_recoveries));
    if (d.trail_restarts > 0)
      std::fprintf(stderr,
                   "  trail        %llu of those restarts: the stops rejected since the bias was measured lay on one "
                   "line against temperature (a drift faster than assumed without a model); the heading was mended "
                   "along it and the temperature model starts from it\n",
                   static_cast<unsigned long long>(d.trail_restarts));
    if (d.saved_noise_replaced > 0)
      std::fprintf(stderr,
                   "  saved noise  sigma_still measured again: the saved one did not fit the first still segment "
                   "(a changed rate or bandwidth, another sensor)\n");
    if (d.saved_bias_restarts > 0)
      std::fprintf(stderr,
                   "  saved bias   refused by the first still segment: the zero-rate level moved while headingd "
                   "was down (one of the restarts above)\n");
    if (d.recoveries_taken_back > 0)
      std::fprintf(stderr,
                   "  taken back   %llu of those restarts: a stop after them agreed with the level they replaced "
                   "(the quiet period was a slow turn)\n",
                   static_cast<unsigned long long>(d.recoveries_taken_back));
    if (d.returns_mended > 0)
      std::fprintf(stderr,
                   "  returned     %llu restarts back to a level an earlier stop measured: the heading since that "
                   "stop was corrected once a later stop agreed (last by %+.1f deg)\n",
                   static_cast<unsigned long long>(d.returns_mended), d.last_return_correction_deg);
    if (d.gaps_bridged > 0)
      std::fprintf(stderr,
                   "  gaps         %llu in the samples, %.2f s in all, bridged at the rate on either side (each "
                   "ended the segment under way; the heading sigma took what the rates left open)\n",
                   static_cast<unsigned long long>(d.gaps_bridged), d.gaps_bridged_s);
    if (d.refused_recoveries > 0)
      std::fprintf(stderr,
                   "  refused      %llu quiet periods steady at a level the confirmed bias could not have drifted "
                   "to (a creep or a slow curve held for minutes): no restart\n",
                   static_cast<unsigned long long>(d.refused_recoveries));
    if (d.refuted_models > 0)
      std::fprintf(stderr,
                   "  refuted      %llu temperature models (per axis) whose slope a long quiet period's own level "
                   "contradicted: forgotten and learned again\n",
                   static_cast<unsigned long long>(d.refuted_models));
    const core::TemperatureModelState& model = d.temperature[2];
    if (model.ready) {
      std::fprintf(stderr, "  temperature  z bias slope %+.5f dps/C over a %.1f C span (%u segments)\n",
                   model.slope_dps_per_c, model.weighted_span_c, model.points);
    } else {
      std::fprintf(stderr, "  temperature  model not in use yet (span %.1f C, %u segments)\n", model.weighted_span_c,
                   model.points);
    }
  }
  const core::Estimate& last = estimator.last();
  const core::Vec3& bias = last.bias_dps;
  std::fprintf(stderr, "  bias         x %+.4f  y %+.4f  z %+.4f dps\n", bias.x(), bias.y(), bias.z());
  std::fprintf(stderr, "  heading      %+.3f deg at the end (unwrapped), sigma %.3f deg\n", last.heading_deg,
               last.heading_sigma_deg);
}

}  // namespace

void print_summary(const Summary& summary, const core::SampleSource& source, const core::Estimator& estimator) {
  const double span_s = summary.last_t_s - summary.first_t_s;
  const auto samples = static_cast<double>(summary.samples);
  std::fprintf(stderr, "headingd %s: %s (%s)\n", summary.command.c_str(), source.describe().c_str(),
               summary.ending.c_str());
  std::fprintf(stderr, "  samples      %llu over %.1f s (%.1f Hz)\n", static_cast<unsigned long long>(summary.samples),
               span_s, span_s > 0 ? (samples - 1.0) / span_s : 0.0);
  if (const std::string counters = source.counters_text(); !counters.empty())
    std::fprintf(stderr, "  sensor       %s\n", counters.c_str());
  if (summary.command != "record") print_estimator(estimator);  // a recording is the samples alone
  if (summary.output) {
    std::fprintf(stderr, "  estimates    %llu rows to %s\n", static_cast<unsigned long long>(summary.rows),
                 *summary.output == "-" ? "standard output" : summary.output->c_str());
  }
  if (summary.recording) std::fprintf(stderr, "  recording    %s\n", summary.recording->c_str());
  const double wall_s = summary.wall_s;
  // A paced replay or a live run does a few thousand samples a second: "0.00 million" said nothing.
  const double per_s = wall_s > 0 ? samples / wall_s : 0.0;
  std::array<char, 48> rate{};
  if (per_s >= 1e6)
    std::snprintf(rate.data(), rate.size(), "%.2f million samples/s", per_s / 1e6);
  else
    std::snprintf(rate.data(), rate.size(), "%.0f samples/s", per_s);
  std::fprintf(stderr, "  speed        %.2f s wall, %s, %.0fx real time\n", wall_s, rate.data(),
               wall_s > 0 ? span_s / wall_s : 0.0);
}

}  // namespace headingd::app
