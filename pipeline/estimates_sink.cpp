#include "pipeline/estimates_sink.hpp"

#include <cmath>

namespace headingd::pipeline {
namespace {
// A recording does not say its rate before it is read: size for the fastest L3GD20H setting.
constexpr double kUnknownSourceRateHz = 800.0;
}  // namespace

std::optional<std::string> check_output_rate(double rate_hz) {
  if (!(rate_hz >= 0.0) || !std::isfinite(rate_hz))
    return "--output-rate must be 0 (every sample) or a positive rate in Hz";
  return std::nullopt;
}

EstimatesSink::EstimatesSink(const std::string& path, double output_rate_hz, double source_rate_hz, double segment_s)
    : out_(path) {
  const double source_hz = source_rate_hz > 0 ? source_rate_hz : kUnknownSourceRateHz;
  const double rows_per_second = output_rate_hz > 0 ? std::min(output_rate_hz, source_hz) : source_hz;
  writer_ = std::make_unique<app::EstimatesWriter>(out_, output_rate_hz,
                                                   static_cast<std::size_t>(std::ceil(rows_per_second * segment_s)));
}

void EstimatesSink::add(const core::Sample& /*sample*/, const core::Estimate& estimate,
                        const core::Estimator& /*estimator*/) {
  writer_->add(estimate);
}

void EstimatesSink::finish(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) {
  writer_->finish();
  out_.close();
}

}  // namespace headingd::pipeline
