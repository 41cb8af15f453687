#include "core/bias_tracker.hpp"

#include <cmath>

namespace headingd::core {
namespace {

// A perfectly constant still signal (a test, or a sensor quantised to one level) has zero
// sigma; a floor far below any real sensor's noise keeps the range test satisfiable.
constexpr double kMinSigmaStillDps = 1e-6;
// Time stamps parsed from text carry rounding; a segment that is short by less than this
// is treated as complete.
constexpr double kTimeEpsilonS = 1e-9;

}  // namespace

std::optional<std::string> validate(const BiasSettings& s) {
  if (!(s.segment_s > 0.0) || !std::isfinite(s.segment_s)) return "segment_s must be a positive number of seconds";
  if (!(s.k_range > 0.0) || !std::isfinite(s.k_range)) return "k_range must be positive";
  if (!(s.k_mean > 0.0) || !std::isfinite(s.k_mean)) return "k_mean must be positive";
  if (s.n_means < 1 || s.n_means > MeanHistory::kMaxMeans)
    return "n_means must be between 1 and " + std::to_string(MeanHistory::kMaxMeans);
  if (s.sigma_still_dps) {
    if (!(s.sigma_still_dps->array() > 0.0).all() || !s.sigma_still_dps->allFinite())
      return "sigma_still_dps must be positive on every axis";
  } else if (!s.still_at_start) {
    return "sigma_still_dps must be set when still_at_start is false";
  }
  return std::nullopt;
}

BiasTracker::BiasTracker(Method method, const BiasSettings& settings)
    : method_(method), settings_(settings), history_(settings.n_means), in_startup_(settings.still_at_start) {
  if (settings_.sigma_still_dps) sigma_still_dps_ = *settings_.sigma_still_dps;
}

void BiasTracker::set_bias(const Vec3& bias_dps) {
  bias_dps_ = bias_dps;
  history_.clear();
  history_.push(bias_dps);
}

SegmentVerdict BiasTracker::update(const Sample& sample) {
  SegmentVerdict verdict;
  if (!started_) {
    started_ = true;
    segment_start_s_ = sample.t_s;
  } else if (sample.t_s - segment_start_s_ >= settings_.segment_s - kTimeEpsilonS) {
    verdict = in_startup_ ? close_startup_segment() : close_segment();
    segment_.reset();
    segment_start_s_ = sample.t_s;
    ++segment_index_;
  }
  segment_.add(sample.rate_dps);
  return verdict;
}

SegmentVerdict BiasTracker::close_startup_segment() {
  in_startup_ = false;
  SegmentVerdict verdict{.closed = true, .index = segment_index_};
  if (!settings_.sigma_still_dps) {
    sigma_still_dps_ = segment_.sigma_dps().cwiseMax(kMinSigmaStillDps);
  }
  bias_dps_ = segment_.mean_dps();
  history_.clear();
  history_.push(bias_dps_);
  verdict.range_ok = verdict.mean_ok = verdict.accepted = true;
  ++accepted_;
  return verdict;
}

SegmentVerdict BiasTracker::close_segment() {
  SegmentVerdict verdict{.closed = true, .index = segment_index_};
  verdict.range_ok = range_says_still(segment_, sigma_still_dps_, settings_.k_range);
  verdict.mean_ok = history_.consistent(segment_.mean_dps(), sigma_still_dps_, settings_.k_mean);
  switch (method_) {
    case Method::A:
      verdict.accepted = false;
      break;
    case Method::B:
      verdict.accepted = verdict.range_ok;
      break;
    case Method::C:
      verdict.accepted = verdict.range_ok && verdict.mean_ok;
      break;
    case Method::Auto:
      verdict.accepted = false;
      break;  // not this tracker's method
  }
  if (verdict.accepted) {
    bias_dps_ = segment_.mean_dps();
    history_.push(bias_dps_);
    ++accepted_;
  } else {
    ++rejected_;
  }
  return verdict;
}

}  // namespace headingd::core
