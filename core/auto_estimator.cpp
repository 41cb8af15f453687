// AutoEstimator: construction, outside edits (bias, heading fixes), the per-sample path
// (segments, range gate, temperature, propagation) and the estimate it reports. The verdict on
// a closed segment is in auto_estimator_verdicts.cpp, the start-up in auto_estimator_startup.cpp,
// restarts of a wrong bias in auto_estimator_recovery.cpp.
#include "core/auto_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "core/units.hpp"

// The steps every sample takes, inlined into update() and advance() alike.
#define HEADINGD_HOT [[gnu::always_inline]] inline

namespace headingd::core {

AutoEstimator::AutoEstimator(const BiasSettings& segments, const AutoSettings& settings)
    : segments_(segments),
      settings_(settings),
      scale_(settings.scale_factor_sigma),
      models_(segments, settings),
      walk_dps2_per_s_(settings.bias_walk_dps_rt_s * settings.bias_walk_dps_rt_s),
      in_startup_(segments.still_at_start) {
  segment_.blocks = BlockMeans(settings_.block_s);
  if (!in_startup_) {
    // Before anything is known the bias could be anywhere within the chip's zero-rate level.
    for (auto& filter : filters_) filter.reset(0.0, settings.zero_rate_sigma_dps * settings.zero_rate_sigma_dps);
  }
}

void AutoEstimator::set_bias(const Vec3& bias_dps, const Vec3& sigma_dps) {
  for (int axis = 0; axis < 3; ++axis)
    filters_[static_cast<std::size_t>(axis)].set_bias(bias_dps[axis], sigma_dps[axis] * sigma_dps[axis]);
  in_startup_ = false;
  bias_measured_at(std::numeric_limits<double>::quiet_NaN());  // at the next temperature read
  commit_last_accepted();                                      // nothing to take back across a bias set from outside
  outlier_ = Outlier{};
  replaced_.pending = false;
  // A restored bias is not confirmed until a stop after motion agrees with it; it has been the
  // bias from now (or the first sample) on, which a restart's correction goes back to.
  bias_from_startup_only_ = true;
  startup_start_t_s_ = started_ ? previous_t_s_ : std::numeric_limits<double>::quiet_NaN();
  bias_confirmed_ = false;
  motion_since_basis_ = false;
  restored_level_open_ = false;  // until doubt_restored_level() says it was saved before a restart
  noise_check_open_ = false;
}

bool AutoEstimator::settle_restored_noise() {
  // sigma_still scales the range gate (k_range of it over a segment): restored from a run at
  // another rate or bandwidth, or from another sensor, a figure too small cuts every segment,
  // nothing is judged still again and the bias is never measured (a state saved at 25 Hz, run at
  // 400 Hz: 0 segments judged in 15 minutes of a simulated AGV), and the file saved at the end
  // keeps the figure, so every later start is the same. A start-up without state takes its
  // figure from its first segment; a restart checks the restored one against the same seconds,
  // or against the first segment after them that does not look like motion (a restart on the move).
  if (segment_.stats.count() < 2 || looks_moving(segment_.stats, segment_.blocks, segment_.duration_s)) return false;
  noise_check_open_ = false;
  const Vec3 measured = segment_.stats.sigma_dps();
  const Vec3 restored = models_.sigma_still_dps();
  const bool misfit = (measured.array() > kNoiseMisfit * restored.array()).any() ||
                      (kNoiseMisfit * measured.array() < restored.array()).any();
  if (misfit && models_.replace_sigma_still(measured)) {
    ++saved_noise_replaced_;
    // A segment on the move that does not look like motion is white vibration as often as a still
    // sensor: the first accepted still segment may lower the figure once more.
    noise_recheck_open_ = (measured.array() > restored.array()).any();
  }
  const Vec3 range = segment_.stats.max_dps() - segment_.stats.min_dps();
  return !(range.array() > settings_.k_range * models_.sigma_still_dps().array()).any();
}

void AutoEstimator::carry_restored_bias(double saved_c, double measured_c) {
  if (!std::isfinite(saved_c)) return;
  restored_at_c_ = saved_c;
  restored_measured_c_ = std::isfinite(measured_c) ? measured_c : saved_c;
  if (started_) follow_restored_temperature(previous_t_s_);
}

void AutoEstimator::follow_restored_temperature(double t_s) {
  const double now_c = previous_temp_c_;
  if (!std::isfinite(now_c)) return;  // no reading yet: follow_temperature() tries again
  const double saved_c = restored_at_c_, measured_c = restored_measured_c_;
  restored_at_c_ = restored_measured_c_ = std::numeric_limits<double>::quiet_NaN();
  // As if the bias had been measured at `measured` and followed the temperature to `saved`
  // while running (its saved sigma holds that share): the step to now adds the rest of it.
  // No time passes in the step, so the heading gains no cross term; the angle the bias error
  // costs from here is propagated from the widened bias variance as always.
  temp_at_bias_c_.fill(measured_c);
  temp_change_integral_c_s_.fill(0.0);
  temp_at_still_c_ = measured_c;
  previous_temp_c_ = saved_c;
  temp_change_t_s_ = t_s;
  follow_temperature(now_c, t_s);
  previous_temp_c_ = now_c;
}

double AutoEstimator::set_heading(double heading_deg, double variance_deg2) {
  const double before_deg = filters_[2].angle_deg();
  const double shown_before_deg = before_deg + shown_undecided_deg_;  // as last shown
  // A fix names a direction; the turns counted so far are ours: the equivalent nearest to the
  // heading now (a fix of 90 at an unwrapped 449 is 450, not a jump of 359 degrees).
  const double fix_deg = before_deg + std::remainder(heading_deg - before_deg, 360.0);
  const double innovation_deg = std::remainder(heading_deg - shown_before_deg, 360.0);
  const bool within_gate = fix_within_gate(innovation_deg, variance_deg2);
  if (within_gate) note_fix_innovation(innovation_deg, variance_deg2);
  // The scale factor's share (as it was before this fix) enters the fix's weighting; after it,
  // turning counts from here.
  const double scale_share_deg2 = scale_variance_deg2();
  scale_.learn(fix_deg - before_deg, before_deg - turned_from_deg_, filters_[2].angle_variance(), variance_deg2);
  filters_[2].widen_angle(scale_share_deg2);
  if (variance_deg2 <= 0.0) {
    filters_[2].fix_angle(fix_deg);
  } else if (!within_gate) {
    // Far outside the sigma: a frame being set (the vehicle's first absolute heading, known to a
    // few degrees, against our 0 +- 0.03 at start-up) or a wrong fix. Weighed as a measurement it
    // would barely move the heading and would push its whole innovation into the bias through
    // their correlation (0.5 rad at 1e-7 rad^2 left a still gyro turning 0.3 deg/s). Taken as the
    // new reference instead: the heading and its variance are the fix's, the bias is untouched.
    filters_[2].restore_angle(fix_deg, variance_deg2);
  } else {
    filters_[2].measure_angle(fix_deg, variance_deg2);
  }
  fixed_angle_variance_deg2_ = std::max(0.0, filters_[2].angle_variance());
  // The segment under way must not take this back if it turns out still, nor may a
  // retraction of the segment before it (its states predate the fix).
  segment_.filters_at_start[2] = filters_[2].state();
  commit_last_accepted();
  outlier_ = Outlier{};
  replaced_.pending = false;       // its angles predate the fix
  return_correction_deg_.reset();  // and so does a correction held for a return,
  history_.forget();               // and every heading the history kept
  count_turns_from_here();
  shown_undecided_deg_ = 0.0;
  return filters_[2].angle_deg() - shown_before_deg;
}

bool AutoEstimator::fix_within_gate(double innovation_deg, double fix_variance_deg2) const {
  // Only a fix that states its uncertainty is a measurement: an "exact" one (variance 0) is as
  // often a frame being set (the dock is 0) as a heading measured, and one many sigma away
  // is a wrong fix or such a frame, not news of the heading (ScaleFactor gates alike).
  if (!(fix_variance_deg2 > 0.0)) return false;
  const double predicted = shown_heading_variance_deg2() + fix_variance_deg2;
  return innovation_deg * innovation_deg <= kFixGateSigmas * kFixGateSigmas * predicted;
}

void AutoEstimator::note_fix_innovation(double innovation_deg, double fix_variance_deg2) {
  // What the heading shown was off by, against what the sigma shown claimed: the share the
  // stops' factor scales (gathered since the last fix) and what it does not.
  const double angle = std::max(0.0, filters_[2].angle_variance());
  const double unscaled =
      std::min(angle, fixed_angle_variance_deg2_) + scale_variance_deg2() + std::max(0.0, fix_variance_deg2);
  fix_innovations_.add(innovation_deg * innovation_deg - unscaled, angle - fixed_angle_variance_deg2_, unscaled);
}

void AutoEstimator::restore_heading(double heading_deg, double variance_deg2) {
  filters_[2].restore_angle(heading_deg, variance_deg2);  // the variance saved includes the scale's
  fixed_angle_variance_deg2_ = std::max(0.0, filters_[2].angle_variance());
  replaced_.pending = false;
  count_turns_from_here();
  segment_.filters_at_start[2] = filters_[2].state();
  estimate_.heading_deg = heading_deg;
}

void AutoEstimator::begin_segment(double t_s) {
  segment_.stats.reset();
  segment_.blocks.reset();
  segment_.duration_s = 0.0;
  segment_.temp_sum_c = 0.0;
  segment_.temp_count = 0;
  segment_.start_t_s = t_s;
  for (std::size_t axis = 0; axis < 3; ++axis) segment_.filters_at_start[axis] = filters_[axis].state();
  segment_.attitude_at_start = attitude_.attitude();
  segment_.temperature_shift_dps.setZero();
  segment_.temperature_shift_var.setZero();
  segment_.history_at_start = history_.mark();
}

HEADINGD_HOT void AutoEstimator::add_to_segment(const Sample& sample, double dt_s) {
  segment_.stats.add(sample.rate_dps);
  segment_.blocks.add(sample.rate_dps, dt_s);
  segment_.duration_s += dt_s;
  if (std::isfinite(sample.temp_c)) {
    segment_.temp_sum_c += sample.temp_c;
    ++segment_.temp_count;
  }
}

HEADINGD_HOT bool AutoEstimator::range_gate_trips(const Vec3& rate_dps) const {
  if (segment_.stats.count() == 0) return false;
  const Vec3 low = segment_.stats.min_dps().cwiseMin(rate_dps);
  const Vec3 high = segment_.stats.max_dps().cwiseMax(rate_dps);
  return ((high - low).array() > settings_.k_range * models_.sigma_still_dps().array()).any();
}

HEADINGD_HOT void AutoEstimator::follow_temperature(double temp_c, double t_s) {
  if (std::isfinite(restored_at_c_)) [[unlikely]]
    follow_restored_temperature(t_s);  // the first reading came after the first sample
  // The kept version of a pending recovery: the temperature's integral since (its angle's share).
  if (replaced_.pending && std::isfinite(previous_temp_c_) && std::isfinite(replaced_.temp_at_c)) {
    replaced_.warmed_c_s += (previous_temp_c_ - replaced_.temp_at_c) * std::max(0.0, t_s - replaced_.warmed_t_s);
    replaced_.warmed_t_s = t_s;
  }
  if (!models_.follows_temperature(temp_c, previous_temp_c_)) return;
  for (int axis = 0; axis < 3; ++axis) {
    double shift = 0.0, slope_variance = 0.0;
    const bool modelled = models_.temperature_shift(axis, temp_c, previous_temp_c_, shift, slope_variance);
    if (!modelled) slope_variance = settings_.unmodelled_bias_per_c_dps * settings_.unmodelled_bias_per_c_dps;
    // The slope's error k is one number, not a new draw per step: since the bias was measured
    // at T0 its error has been k (T - T0) and the angle's -k times the integral of (T - T0)
    // dt, a rank-one covariance that grows with the temperature's change. Propagation makes
    // the angle's share of it from the bias's; added here is what it leaves out (none of the
    // angle's variance, part of the cross term), so that a stop measuring the bias corrects
    // the heading integrated meanwhile in the right proportion. A change back towards T0
    // takes no variance away (the model may be curved). A retraction does not restore T0: the
    // share restarts at the retracted segment's temperature, a little narrow until the next stop.
    const auto i = static_cast<std::size_t>(axis);
    if (!std::isfinite(temp_at_bias_c_[i])) {  // restored, or started without a still segment
      temp_at_bias_c_[i] = previous_temp_c_;
      temp_change_integral_c_s_[i] = 0.0;
    }
    const double before_c = previous_temp_c_ - temp_at_bias_c_[i];
    const double after_c = temp_c - temp_at_bias_c_[i];
    temp_change_integral_c_s_[i] += before_c * std::max(0.0, t_s - temp_change_t_s_);
    const double variance = std::max(0.0, slope_variance * (after_c * after_c - before_c * before_c));
    const double cross = axis == 2 ? -slope_variance * temp_change_integral_c_s_[i] * (after_c - before_c) : 0.0;
    filters_[i].shift_bias(shift, variance, cross);
    segment_.temperature_shift_dps[axis] += shift;
    segment_.temperature_shift_var[axis] += variance;
  }
  temp_change_t_s_ = t_s;
}

double AutoEstimator::temp_change_integral_now(std::size_t axis) const {
  if (!std::isfinite(temp_at_bias_c_[axis]) || !std::isfinite(previous_temp_c_)) return 0.0;
  const double change_c = previous_temp_c_ - temp_at_bias_c_[axis];
  return temp_change_integral_c_s_[axis] + change_c * std::max(0.0, previous_t_s_ - temp_change_t_s_);
}

void AutoEstimator::bias_measured_at(double temp_c) {
  // A measurement puts the bias right, not the angle a wrong model slope cost meanwhile.
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (!settings_.use_temperature || !models_.temperature_model(static_cast<int>(axis)).ready())
      model_exposure_c_s_[axis] = 0.0;
    else
      model_exposure_c_s_[axis] += temp_change_integral_now(axis);
  }
  temp_at_bias_c_.fill(temp_c);
  bias_measured_t_s_ = previous_t_s_;
  temp_change_integral_c_s_.fill(0.0);
  temp_change_t_s_ = previous_t_s_;
}

// One sample: hold still while the start-up segment measures; otherwise close the segment
// when it is full or the range gate trips (judge it, apply the verdict), propagate the filter
// and the attitude with the sample, and report.
const Estimate& AutoEstimator::update(const Sample& reported) {
  estimate_.closed = SegmentVerdict{};
  reported_temp_c_ = reported.temp_c;
  Sample sample = reported;
  sample.temp_c = temperature_reading_.take(sample.t_s, sample.temp_c);
  if (!started_) {
    start(sample);
    return estimate_;
  }
  const double dt_s = sample.t_s - previous_t_s_;
  if (is_gap(dt_s)) [[unlikely]]
    return bridge_gap(sample, dt_s);
  previous_t_s_ = sample.t_s;
  if (in_startup_ && !segment_full(sample.t_s)) {
    keep_startup_turn(sample.rate_dps, dt_s);
    if (moving_startups_ == 0) {
      hold_during_startup(sample, dt_s);
      return estimate_;
    }
    // After a start-up segment that moved, the next ones are integrated as they come.
    previous_temp_c_ = sample.temp_c;
    add_to_segment(sample, dt_s);
    propagate(sample, dt_s);
    fill_estimate(sample);
    return estimate_;
  }
  estimate_.closed = close_segment_if_due(sample);
  if (in_startup_) {  // the first sample of another start-up segment
    flush_startup_turn();
    startup_turns_before_segment_ = startup_turns_.size();
    keep_startup_turn(sample.rate_dps, dt_s);
  }
  previous_temp_c_ = sample.temp_c;
  add_to_segment(sample, dt_s);
  propagate(sample, dt_s);
  fill_estimate(sample);
  return estimate_;
}

// A gap in the samples — an overrun that lost more than the chip's FIFO held, a chip set up
// again after bus errors, a recording with a hole. Nothing was measured over it. Integrated as
// an ordinary interval, the one sample after it would stand for all of it, its noise times the
// gap's length (a simulated still recording with a 30 s hole: the heading 3.2 deg off, the
// attitude tilted 45 deg, for good), and the segment under way would take a stillness it never
// saw (BROAD's trials with 0.5 s holes every 20 s: as few as 19 % of the moving samples within
// 2 sigma; bench/broad_gaps.sh). Instead the segment ends at the gap, judged on what it has,
// every run across it ends (the stop, the quiet run, the pair a creep test compares), and the
// gap is integrated at the rate the samples on either side agree on, with the doubt they leave.
namespace {

// A gap is an interval this many times the samples' usual one (a time stamp's jitter stays well
// within it), and longer than kMinGapS. Shorter holes are ordinary intervals: an overrun loses a
// FIFO's worth or two (32 samples, 40 ms at 800 Hz), which the sample after it bridges about as
// well as anything, and ending a segment at each would cut a stop into pieces (simulated AGV hour,
// a 60 ms hole every 3 minutes: each hole's heading error RMS 0.017 deg held, 0.026 deg bridged
// with the segment ended; bench/sim_gaps.sh).
constexpr double kGapIntervals = 4.0;
constexpr double kMinGapS = 0.1;
// Samples a segment needs before its mean interval is taken as the usual one.
constexpr std::uint32_t kIntervalSamples = 10;

}  // namespace

double AutoEstimator::gap_threshold_s() const {
  double interval_s = sample_interval_s_;
  if (!(interval_s > 0.0)) {  // the first segment: its own samples so far
    if (segment_.stats.count() < kIntervalSamples) return std::numeric_limits<double>::infinity();
    interval_s = segment_.duration_s / static_cast<double>(segment_.stats.count());
  }
  return std::max(kGapIntervals * interval_s, kMinGapS);
}

bool AutoEstimator::is_gap(double dt_s) const {
  return dt_s > kMinGapS && dt_s > gap_threshold_s();  // the first test nearly always false
}

void AutoEstimator::note_sample_interval() {
  if (segment_.stats.count() >= kIntervalSamples && segment_.duration_s > 0.0)
    sample_interval_s_ = segment_.duration_s / static_cast<double>(segment_.stats.count());
}

const Estimate& AutoEstimator::bridge_gap(const Sample& sample, double gap_s) {
  ++gaps_;
  gaps_s_ += gap_s;
  GapSide before{.rate_dps = segment_.stats.mean_dps()};  // the segment under way has its first sample
  const bool long_enough =
      segment_.duration_s + kTimeEpsilonS >= settings_.min_segment_s && segment_.stats.count() >= 2;
  if (in_startup_) {
    // The start-up segment ends here: judged as start-ups are when long enough; else a held one
    // is dropped (the heading stays where it was held, the next one starts after the gap) and a
    // moving one has been integrated already.
    if (long_enough) {
      estimate_.closed = close_startup();
      before.still = !in_startup_;
    } else if (moving_startups_ == 0) {
      startup_turns_.resize(std::min(startup_turns_.size(), startup_turns_before_segment_));
      pending_turn_ = AttitudeIntegrator::Turn{};
    }
  } else {
    follow_temperature(sample.temp_c, sample.t_s);
    if (long_enough) {
      // The gate did not watch a segment under the noise check: judged as it would have been.
      estimate_.closed = close_segment(noise_check_open_ && !settle_restored_noise());
      before.still = estimate_.closed.accepted;
    } else if (previous_.usable && within_gate(before.rate_dps - previous_.mean_dps)) {
      // A segment just begun that goes on as the whole one before it did (no gate tripped
      // between): that one's mean and verdict say it with many more samples.
      before = {.rate_dps = previous_.mean_dps, .still = previous_accepted_};
    }
    end_runs_at_gap();
  }
  const bool holding = in_startup_ && moving_startups_ == 0;
  if (!holding) integrate_gap(before, sample.rate_dps, gap_s);
  ++segment_index_;
  note_sample_interval();
  begin_segment(sample.t_s);
  if (in_startup_) {
    flush_startup_turn();
    startup_turns_before_segment_ = startup_turns_.size();
  }
  previous_t_s_ = sample.t_s;
  previous_temp_c_ = sample.temp_c;
  add_to_segment(sample, 0.0);
  if (!holding) propagate(sample, 0.0);
  fill_estimate(sample);
  return estimate_;
}

bool AutoEstimator::within_gate(const Vec3& change_dps) const {
  return (change_dps.cwiseAbs().array() <= (settings_.k_range * models_.sigma_still_dps()).array()).all();
}

void AutoEstimator::end_runs_at_gap() {
  // As a cut does: nothing unseen is still, and nothing on either side is the same segment's
  // neighbour. Motion is not claimed either (a gap may fall inside a stop).
  replaced_.quiet_run_over = true;
  previous_.usable = false;
  quiet_.duration_s = 0.0;
  commit_last_accepted();
  outlier_ = Outlier{};
}

void AutoEstimator::integrate_gap(const GapSide& before, const Vec3& after_dps, double gap_s) {
  // The sample after the gap within the range gate of the rate before it: the platform did as
  // it did, and the rate before it, many samples' worth, says it best — or, where that was a
  // stop, the bias (no turn), which all the stop's samples measured. Otherwise the rate changed
  // somewhere in the gap, and nothing says where or how: the turn is taken halfway between the
  // two, and anything from none to the faster of them over the whole gap is as likely (half
  // that turn as the angle's doubt; all axes, as a tilted platform's heading takes turns about
  // x and y).
  const Vec3 change_dps = after_dps - before.rate_dps;
  const bool steady = within_gate(change_dps);
  const bool held_still = steady && before.still;
  Sample bridge;
  bridge.rate_dps = !steady ? Vec3(0.5 * (before.rate_dps + after_dps)) : held_still ? bias_dps() : before.rate_dps;
  history_.integrate(bridge.rate_dps.z(), gap_s);
  filters_[0].let_bias_drift(gap_s, walk_dps2_per_s_);
  filters_[1].let_bias_drift(gap_s, walk_dps2_per_s_);
  // Held still, the angle is held as over a still segment: no bias error is integrated into it
  // (a suspend of hours would otherwise carry the whole walk into the sigma and, through the
  // angle-bias covariance, let the next stop's bias move the heading by its change times hours).
  if (held_still)
    filters_[2].let_bias_drift(gap_s, walk_dps2_per_s_);
  else
    filters_[2].propagate(rate_for_angle(bridge.rate_dps, 2), gap_s, models_.white_dps2_s()[2], walk_dps2_per_s_);
  if (!steady) {
    const Vec3 bias = bias_dps();
    const double fastest_dps =
        std::max({change_dps.norm(), (before.rate_dps - bias).norm(), (after_dps - bias).norm()}) * scale_.gain();
    const double doubt_deg = 0.5 * fastest_dps * gap_s;
    filters_[2].widen_angle(doubt_deg * doubt_deg);
  }
  if (in_startup_) {  // a moving start-up's turns are integrated again once a bias is measured
    keep_startup_turn(bridge.rate_dps, gap_s);
    flush_startup_turn();
  }
  const AttitudeIntegrator::Turn turn = turn_of(bridge, gap_s);
  attitude_.add_all(&turn, 1);
}

void AutoEstimator::start(const Sample& sample) {
  started_ = true;
  if (!std::isfinite(startup_start_t_s_)) startup_start_t_s_ = sample.t_s;
  previous_t_s_ = sample.t_s;
  previous_temp_c_ = sample.temp_c;
  if (std::isfinite(restored_at_c_)) follow_restored_temperature(sample.t_s);
  begin_segment(sample.t_s);
  add_to_segment(sample, 0.0);
  attitude_at_startup_ = attitude_.attitude();
  startup_turns_before_segment_ = 0;
  fill_estimate(sample);
}

HEADINGD_HOT bool AutoEstimator::segment_full(double t_s) const {
  return t_s - segment_.start_t_s >= segments_.segment_s - kTimeEpsilonS;
}

void AutoEstimator::hold_during_startup(const Sample& sample, double dt_s) {
  add_to_segment(sample, dt_s);
  history_.integrate(sample.rate_dps.z(), dt_s);  // a start-up found moving is integrated again
  previous_temp_c_ = sample.temp_c;
  fill_estimate(sample);
}

SegmentVerdict AutoEstimator::close_segment_if_due(const Sample& sample) {
  SegmentVerdict verdict;
  if (in_startup_) {
    verdict = close_startup();  // update() comes here only once the start-up segment is full
  } else {
    follow_temperature(sample.temp_c, sample.t_s);
    const bool full = segment_full(sample.t_s);
    const bool trips = !full && !noise_check_open_ && range_gate_trips(sample.rate_dps);
    if (!full && !trips) return verdict;
    // The first segment after a restart ends on time only; then it is judged as the range gate
    // would have, with the noise figure it showed right.
    const bool moved = trips || (noise_check_open_ && !settle_restored_noise());
    if (moved) restored_level_open_ = false;  // a segment motion cut says nothing of the level
    verdict = close_segment(moved && !trips);
    if (moved) {
      previous_.usable = false;  // motion came between
      motion_since_startup_ = true;
      motion_since_basis_ = true;
    }
  }
  ++segment_index_;
  note_sample_interval();
  begin_segment(sample.t_s);
  return verdict;
}

void AutoEstimator::propagate(const Sample& sample, double dt_s) {
  propagate_filters(sample, dt_s);
  const AttitudeIntegrator::Turn turn = turn_of(sample, dt_s);
  attitude_.add_all(&turn, 1);
}

HEADINGD_HOT void AutoEstimator::propagate_filters(const Sample& sample, double dt_s) {
  models_.track_vibration(sample.rate_dps, dt_s);
  history_.integrate(sample.rate_dps.z(), dt_s);
  // x and y: only the bias half. Their angles and the angles' covariances are never read (the
  // attitude carries roll and pitch), and the bias half does not depend on them.
  filters_[0].let_bias_drift(dt_s, walk_dps2_per_s_);
  filters_[1].let_bias_drift(dt_s, walk_dps2_per_s_);
  filters_[2].propagate(rate_for_angle(sample.rate_dps, 2), dt_s, models_.process_white_dps2_s(2, dt_s),
                        walk_dps2_per_s_);
}

HEADINGD_HOT AttitudeIntegrator::Turn AutoEstimator::turn_of(const Sample& sample, double dt_s) const {
  return {sample.rate_dps.x() - filters_[0].bias_dps(), sample.rate_dps.y() - filters_[1].bias_dps(),
          (sample.rate_dps.z() - filters_[2].bias_dps()) * scale_.gain(), dt_s};
}

HEADINGD_HOT double AutoEstimator::rate_for_angle(const Vec3& rate_dps, int axis) const {
  // The filter integrates (rate - bias): the z turn is corrected by the scale learned from
  // heading fixes, the bias (measured where the rate is zero) is not.
  if (axis != 2) return rate_dps[axis];
  return scaled_z(rate_dps.z(), filters_[2].bias_dps(), scale_.gain());
}

Vec3 AutoEstimator::bias_dps() const {
  return {filters_[0].bias_dps(), filters_[1].bias_dps(), filters_[2].bias_dps()};
}

double AutoEstimator::heading_variance_scale() const {
  if (!settings_.calibrate_sigma) return 1.0;
  return fix_innovations_.variance_scale(stop_innovations_.variance_scale(), kFixScaleFloor);
}

double AutoEstimator::scale_variance_deg2() const {
  // Each axis's scale error multiplies the turn it made about the vertical, independently of the
  // others. z's is taken on the filter's net turn, on which fixes learn it; x's and y's are zero
  // on a level platform and grow on a tilted or hand-held one (BROAD's trials, turned about the
  // vertical through x for minutes: its error grows with that turn, which z's share never saw).
  const Vec3 turned = attitude_.vertical_turn_deg() - vertical_turned_from_deg_;
  const double xy_variance = settings_.scale_factor_sigma * settings_.scale_factor_sigma;
  return scale_.heading_variance_deg2(filters_[2].angle_deg() - turned_from_deg_) +
         xy_variance * (turned.x() * turned.x() + turned.y() * turned.y());
}

double AutoEstimator::shown_heading_variance_deg2() const {
  const double angle = std::max(0.0, filters_[2].angle_variance());
  if (!settings_.calibrate_sigma) return angle + scale_variance_deg2();
  // A fix's (or a restored state's) own variance is the caller's figure, not the filter's.
  const double gathered = std::max(0.0, angle - fixed_angle_variance_deg2_);
  return std::min(angle, fixed_angle_variance_deg2_) + heading_variance_scale() * gathered + scale_variance_deg2();
}

void AutoEstimator::fill_estimate(const Sample& sample) {
  const Vec3 bias = bias_dps();
  estimate_.t_s = sample.t_s;
  estimate_.temp_c = reported_temp_c_;  // what the sensor said, not the estimator's reading of it
  const double undecided_deg = undecided_offset_deg(sample.t_s);
  shown_undecided_deg_ = undecided_deg;
  estimate_.heading_deg = filters_[2].angle_deg() + undecided_deg;
  estimate_.attitude = attitude_.attitude();
  if (undecided_deg != 0.0)
    estimate_.attitude = Eigen::AngleAxisd(deg_to_rad(undecided_deg), Vec3::UnitZ()) * estimate_.attitude;
  estimate_.bias_dps = bias;
  estimate_.rate_dps = sample.rate_dps - bias;
  if (in_startup_ && moving_startups_ == 0) {
    // The heading is held on the assumption that the platform is still, which only the closed
    // segment can show: until then it may be turning at the rate read, less a bias within the
    // zero-rate prior, and the held heading is off by that turn (RMS over the prior: the rate
    // and the prior's sigma in quadrature, times the time held). All three axes: the attitude is
    // held too, and a tilted platform's yaw takes turns about x and y. A sigma of zero here read
    // as "exact" while a platform started in a turn (random world 482: 26 deg at 2 s; BROAD's
    // trials cut to start in a hand's rotation: 0.1 % of the held samples within 2 sigma).
    const double held_s = std::max(0.0, sample.t_s - segment_.start_t_s);
    const double rate_dps = segment_.stats.count() > 0 ? segment_.stats.mean_dps().norm() : 0.0;
    estimate_.heading_sigma_deg = held_s * std::hypot(rate_dps, settings_.zero_rate_sigma_dps);
    estimate_.bias_sigma_dps = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  } else {
    estimate_.heading_sigma_deg = std::sqrt(shown_heading_variance_deg2() + restored_level_doubt_deg2(sample.t_s));
    for (std::size_t axis = 0; axis < 3; ++axis)
      estimate_.bias_sigma_dps[static_cast<Eigen::Index>(axis)] =
          std::sqrt(std::max(0.0, filters_[axis].bias_variance()));
  }
  estimate_.in_startup = in_startup_;
  estimate_.segment_index = segment_index_;
}

std::size_t AutoEstimator::advance(const Sample* samples, std::size_t count, double until_t_s) {
  if (!started_ || in_startup_ || noise_check_open_) return 0;  // update() takes those samples
  estimate_.closed = SegmentVerdict{};
  // In chunks, each in three passes that together do what update() does sample by sample:
  // the tests and the segment's statistics; the three axis filters, their values held in
  // registers; the attitude. The filters and the attitude take the bias in force at each
  // sample, which only a temperature step moves: a chunk starts with such a step or has none.
  constexpr std::size_t kChunk = 128;
  std::array<double, kChunk> dts;
  std::array<AttitudeIntegrator::Turn, kChunk> turns;
  std::array<double, kChunk> temps;
  const Vec3 gate_dps = settings_.k_range * models_.sigma_still_dps();  // the segment under way has samples
  const double gain = scale_.gain();
  const double gap_s = gap_threshold_s();  // a gap is for update() (bridge_gap)
  std::size_t taken = 0;
  bool special = false;
  while (taken < count && !special) {
    const Sample* chunk = samples + taken;
    std::size_t n = 0;
    Vec3 low = segment_.stats.min_dps(), high = segment_.stats.max_dps();
    double previous_t_s = previous_t_s_;
    for (; n < kChunk && taken + n < count; ++n) {
      const Sample& sample = chunk[n];
      // range_gate_trips(), on the running range and the gate worked out once
      const Vec3 low_with = low.cwiseMin(sample.rate_dps), high_with = high.cwiseMax(sample.rate_dps);
      // What update() would close on is left for it (neither test depends on the temperature
      // step, which update() applies first), and so are a sample someone wants the estimate of
      // and one the pipeline's door must refuse.
      if (!(sample.t_s < until_t_s) || !plausible(sample) || segment_full(sample.t_s) ||
          sample.t_s - previous_t_s > gap_s || ((high_with - low_with).array() > gate_dps.array()).any()) {
        special = true;
        break;
      }
      const double temp_c = temperature_reading_.take(sample.t_s, sample.temp_c);  // the same when asked again
      if (n > 0 && models_.follows_temperature(temp_c, previous_temp_c_)) break;   // the next chunk's first
      if (n == 0) follow_temperature(temp_c, sample.t_s);
      previous_temp_c_ = temp_c;
      temps[n] = temp_c;
      low = low_with, high = high_with;
      dts[n] = sample.t_s - previous_t_s;
      previous_t_s = sample.t_s;
      turns[n] = turn_of(sample, dts[n]);
    }
    previous_t_s_ = previous_t_s;
    // add_to_segment(), a run at a time
    segment_.stats.add_run(chunk, n);
    segment_.blocks.add_run(chunk, dts.data(), n);
    for (std::size_t k = 0; k < n; ++k) {
      segment_.duration_s += dts[k];
      if (std::isfinite(temps[k])) {
        segment_.temp_sum_c += temps[k];
        ++segment_.temp_count;
      }
    }
    // propagate_filters(), on plain values
    AxisFilter::Plain z = filters_[2].plain();
    double x_var = filters_[0].bias_variance(), y_var = filters_[1].bias_variance();
    SensorModels::Vibration vibration = models_.vibration();
    for (std::size_t k = 0; k < n; ++k) {
      const double rate = chunk[k].rate_dps.z();
      const double dt_s = dts[k];
      SensorModels::step(vibration, rate, dt_s);
      history_.integrate(rate, dt_s);
      x_var += walk_dps2_per_s_ * dt_s;
      y_var += walk_dps2_per_s_ * dt_s;
      AxisFilter::propagate(z, scaled_z(rate, z.bias_dps, gain), dt_s, models_.white_z_dps2_s(vibration, dt_s),
                            walk_dps2_per_s_);
    }
    models_.set_vibration(vibration);
    filters_[0].set_bias_variance(x_var);
    filters_[1].set_bias_variance(y_var);
    filters_[2].set_plain(z);
    attitude_.add_all(turns.data(), n);
    taken += n;
  }
  if (taken > 0) {
    reported_temp_c_ = samples[taken - 1].temp_c;
    fill_estimate(samples[taken - 1]);
  }
  return taken;
}

}  // namespace headingd::core
