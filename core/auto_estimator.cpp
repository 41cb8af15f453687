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
namespace {

constexpr double kTimeEpsilonS = 1e-9;
// A segment under a "stopped" hint whose mean is this far from the bias turns, whatever the
// hint says: thermal drift of the bias is hundredths of a dps per segment, not tenths.
constexpr double kHintConflictDps = 0.3;
constexpr double kHintConflictSigmas = 10.0;
// How often a segment that passed the range gate turns out a slow turn is learned from the
// run: the configured creep_prior counts as this many segments, and a verdict's weight halves
// over about 140 segments (7 minutes of stops).
constexpr double kPriorSegments = 20.0;
// How far a confirmed bias may have moved when a quiet run would restart it: the bias walk's
// sigmas, the zero-rate level's change with temperature (datasheet OffDr: +-0.04 dps/C at
// 2000 dps full scale, the widest range), and a floor for what neither models: a consumer
// MEMS gyro's bias instability, up to some 20 deg/h (0.005 dps). Not more: a creep held past
// the wait is a quiet run too, and every hundredth of a dps let through restarts the bias on
// slow turns (0.02 here cost issue 12's random worlds half their median, bench/sweep.sh).
constexpr double kPlausibleSigmas = 5.0;
constexpr double kZeroRateChangeDpsPerC = 0.04;
constexpr double kPlausibleFloorDps = 0.005;
constexpr double kModelMisfitDpsPerC = 0.003;  // a linear fit to a curved bias, per C of change
// A quiet run's slope against temperature this many sigmas (its own, the model's and a floor)
// from the model's refutes the model. Forgetting a model costs little (it is learned again
// from the next stops), keeping a wrong one a stop rejected for its whole length; but the test
// is asked again on every segment of a long run, hence 4 and not 3 (at 3, a creep refuted a
// right model on random world 21). The floor: the model's slope sigma takes every accepted
// segment as independent, and a curved bias's slope differs from a line's. Picked from
// 0.003/0.0015/0.001 on the sweep.
constexpr double kRefuteSigmas = 4.0;
constexpr double kSlopeFloorDpsPerC = 0.001;
constexpr double kUnconditionalRecoveryFactor = 10.0;
constexpr double kMostlyRejecting = 0.8;
constexpr double kFewVerdicts = 5.0;
constexpr double kFastestCreepDps = 0.5;  // issue 12's creeps: 0.02-0.5 dps
// The odds that an undecided recovery's quiet run was a creep, against a stop, fall with the
// square of how long it has held still, from even at the wait (see undecided_offset_deg).
constexpr double kCreepOddsPower = 2.0;
constexpr double kVerdictMemory = 0.995;
constexpr std::size_t kVerdictRecords = 1024;  // 0.995^1024: under 1 % of a verdict's weight is left
// A start-up segment whose block means scatter this many times more than its samples' white
// noise allows is motion; after this many of them (5 minutes) the next is the start-up whatever
// it looks like (a platform vibrating slowly where it stands would otherwise never start). Not
// fewer: a vehicle or a hand may move for minutes before its first stop (BROAD's tapping and
// vibration trials move for two, and a start-up forced inside that was a wrong bias).
constexpr double kMovingStartupRatio = 15.0;
constexpr int kMaxMovingStartups = 100;
// A still segment's block means scatter about one level; where motion starts or stops inside a
// segment, they move from one level to another, and the segment's mean lies anywhere between
// (random world 108: the last seconds of a 0.2 dps curve and the first of a stop, accepted
// under a bias sigma widened by a warm-up, measured the bias 0.12 dps off and taught the
// temperature model the wrong sign). The least-squares slope of the block means against time,
// in sigmas of the block means' own noise, flags such a segment whatever its mean. 6 sigmas:
// the maximum over three axes on still segments is 1.3 in the median and above 4 on 4 of some
// 13500 (random worlds 5, 7, 14, 17, 25, 33, 41, 108: a Gaussian's share), on BROAD's accepted
// rests at most 3.4; the transitions that cost the random worlds lie at 7-24. At 4 and 5, BROAD
// trial 05 lost a segment where the hand began to move before the dataset's mark (5.0).
constexpr double kRateChangeSigmas = 6.0;
constexpr double kStartupTurnS = 0.005;  // the start-up's samples are kept this long at a time
// What the wait before a restart is worth, in nats: odds of 20 to 1 that a run held that long is
// a stop and not a steady turn.
constexpr double kWaitEvidence = 3.0;
// A restart's level is the one an earlier stop measured when they lie within this many sigmas of
// their spread and the bias walk between (core/bias_history.hpp).
constexpr double kReturnSigmas = 3.0;

}  // namespace

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
}

double AutoEstimator::set_heading(double heading_deg, double variance_deg2) {
  const double before_deg = filters_[2].angle_deg();
  const double shown_before_deg = before_deg + shown_undecided_deg_;  // as last shown
  // A fix names a direction; the turns counted so far are ours: the equivalent nearest to the
  // heading now (a fix of 90 at an unwrapped 449 is 450, not a jump of 359 degrees).
  const double fix_deg = before_deg + std::remainder(heading_deg - before_deg, 360.0);
  // The scale factor's share (as it was before this fix) enters the fix's weighting; after it,
  // turning counts from here.
  const double scale_share_deg2 = scale_variance_deg2();
  scale_.learn(fix_deg - before_deg, before_deg - turned_from_deg_, filters_[2].angle_variance(), variance_deg2);
  filters_[2].widen_angle(scale_share_deg2);
  if (variance_deg2 <= 0.0) {
    filters_[2].fix_angle(fix_deg);
  } else {
    filters_[2].measure_angle(fix_deg, variance_deg2);
  }
  // The segment under way must not take this back if it turns out still, nor may a
  // retraction of the segment before it (its states predate the fix).
  segment_.filters_at_start[2] = filters_[2].state();
  commit_last_accepted();
  outlier_ = Outlier{};
  replaced_.pending = false;       // its angles predate the fix
  return_correction_deg_.reset();  // and so does a correction held for a return,
  history_.forget();               // and every heading the history kept
  turned_from_deg_ = filters_[2].angle_deg();
  shown_undecided_deg_ = 0.0;
  return filters_[2].angle_deg() - shown_before_deg;
}

void AutoEstimator::restore_heading(double heading_deg, double variance_deg2) {
  filters_[2].restore_angle(heading_deg, variance_deg2);  // the variance saved includes the scale's
  replaced_.pending = false;
  turned_from_deg_ = heading_deg;
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

bool AutoEstimator::startup_looks_moving() const {
  // Still, the segment's 0.1 s block means scatter as its white noise allows (the chip's
  // low-pass can make that a few times the samples' own variance at high rates); a hand or a
  // vehicle turning moves them by the motion, tens of times more (BROAD's rotations: 20-29).
  NoiseDensity blocks_only;
  blocks_only.add(segment_.blocks);
  if (!blocks_only.known() || segment_.stats.count() < 2) return false;
  const double dt_s = segment_.duration_s / static_cast<double>(segment_.stats.count());
  const Vec3 from_samples = segment_.stats.sigma_dps().cwiseAbs2() * dt_s;
  return (blocks_only.density_squared().array() > kMovingStartupRatio * from_samples.array()).any();
}

bool AutoEstimator::rate_changed_within_segment() const {
  const BlockMeans& blocks = segment_.blocks;
  if (blocks.blocks() < 3 || segment_.stats.count() < 2) return false;
  // A block mean's variance: the white noise's over a block, or the samples' own where they
  // scatter more (vibration, white at the sample rate, leaves no trend in the blocks).
  const double dt_s = segment_.duration_s / static_cast<double>(segment_.stats.count());
  const Vec3 per_sample = segment_.stats.sigma_dps().cwiseAbs2() * dt_s;
  const Vec3 block_variance = models_.white_dps2_s().cwiseMax(per_sample) / blocks.block_s();
  const Vec3 trend = blocks.trend_per_block();
  for (Eigen::Index a = 0; a < 3; ++a) {
    if (trend[a] * trend[a] > kRateChangeSigmas * kRateChangeSigmas * block_variance[a] / blocks.index_spread())
      return true;
  }
  return false;
}

SegmentVerdict AutoEstimator::pass_moving_startup() {
  // Not a start-up: the heading takes the segment's turn with the bias's prior (zero, within
  // zero_rate_sigma_dps), and the still start-up to come measures the bias and, through the
  // angle-bias covariance, corrects what was integrated meanwhile.
  // The first one was held still as start-ups are: it is integrated now, in one step; the
  // ones after it are integrated sample by sample (update()).
  SegmentVerdict verdict{.closed = true, .index = segment_index_};
  if (moving_startups_++ > 0) return verdict;
  const double prior_dps2 = settings_.zero_rate_sigma_dps * settings_.zero_rate_sigma_dps;
  const Vec3 mean = segment_.stats.mean_dps();
  for (std::size_t axis = 0; axis < 3; ++axis) {
    filters_[axis].reset(0.0, prior_dps2);
    AxisFilter::Plain p = filters_[axis].plain();
    AxisFilter::propagate(p, mean[static_cast<Eigen::Index>(axis)], segment_.duration_s, 0.0, walk_dps2_per_s_);
    filters_[axis].set_plain(p);
  }
  flush_startup_turn();
  attitude_.set_attitude(startup_attitude_with_bias(Vec3::Zero(), startup_turns_.size()));
  return verdict;
}

void AutoEstimator::keep_startup_turn(const Vec3& rate_dps, double dt_s) {
  // Kept 5 ms at a time (their mean rate): five minutes at 8 kHz would be 70 MB a sample at a
  // time, and 2 MB so. Not longer: averaging over 0.1 s cost BROAD's fast rotations (several
  // hundred dps) half their heading again (bench/broad_moving_start.sh, broad-08: 22 -> 57 deg).
  pending_turn_.x_dps += rate_dps.x() * dt_s;
  pending_turn_.y_dps += rate_dps.y() * dt_s;
  pending_turn_.z_dps += rate_dps.z() * dt_s;
  pending_turn_.dt_s += dt_s;
  if (pending_turn_.dt_s + kTimeEpsilonS >= kStartupTurnS) flush_startup_turn();
}

void AutoEstimator::flush_startup_turn() {
  if (pending_turn_.dt_s <= 0.0) return;
  const double dt_s = pending_turn_.dt_s;
  startup_turns_.push_back({pending_turn_.x_dps / dt_s, pending_turn_.y_dps / dt_s, pending_turn_.z_dps / dt_s, dt_s});
  pending_turn_ = AttitudeIntegrator::Turn{};
}

Eigen::Quaterniond AutoEstimator::startup_attitude_with_bias(const Vec3& bias_dps, std::size_t count) const {
  AttitudeIntegrator again;
  again.set_attitude(attitude_at_startup_);
  for (std::size_t i = 0; i < std::min(count, startup_turns_.size()); ++i) {
    const AttitudeIntegrator::Turn& t = startup_turns_[i];
    again.add(Vec3(t.x_dps, t.y_dps, t.z_dps) - bias_dps, t.dt_s);
  }
  return again.attitude();
}

SegmentVerdict AutoEstimator::close_startup() {
  if (moving_startups_ < kMaxMovingStartups && startup_looks_moving()) return pass_moving_startup();
  in_startup_ = false;
  SegmentVerdict verdict{.closed = true, .index = segment_index_, .range_ok = true, .mean_ok = true, .accepted = true};
  const auto& stats = segment_.stats;
  const double duration_s = std::max(segment_.duration_s, kTimeEpsilonS);
  models_.learn_from_startup(stats, segment_.blocks, duration_s);
  const Vec3 r = models_.white_dps2_s() / duration_s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    if (moving_startups_ == 0) {
      filters_[axis].reset(stats.mean_dps()[a], r[a]);
    } else {
      // After start-up segments that moved: a zero-rate update over this one, and the level
      // taken for the bias since the first sample, as any start-up's is: through the covariance
      // the heading they ran on the prior takes it (the whole of it, as a restart's correction
      // later assumes), and the bias variance is the mean's.
      filters_[axis].restore(segment_.filters_at_start[axis]);
      filters_[axis].measure_bias(stats.mean_dps()[a], 0.0);
      filters_[axis].set_bias_variance(r[a]);
    }
  }
  // The attitude: the motion before this segment with the bias just measured; over it, none.
  if (moving_startups_ > 0)
    attitude_.set_attitude(startup_attitude_with_bias(stats.mean_dps(), startup_turns_before_segment_));
  std::vector<AttitudeIntegrator::Turn>().swap(startup_turns_);
  pending_turn_ = AttitudeIntegrator::Turn{};
  if (segment_.temp_count > 0) {
    models_.add_temperature_point(segment_.start_t_s + 0.5 * duration_s, segment_.temp_sum_c / segment_.temp_count,
                                  stats.mean_dps(), r);
  }
  ++accepted_;
  last_still_t_s_ = segment_.start_t_s + duration_s;
  history_.measured(last_still_t_s_, filters_[2].bias_dps(), filters_[2].bias_variance(), filters_[2].angle_deg());
  bias_confirmed_ = false;
  motion_since_basis_ = false;
  if (segment_.temp_count > 0) temp_at_still_c_ = segment_.temp_sum_c / segment_.temp_count;
  bias_measured_at(temp_at_still_c_);
  bias_from_startup_only_ = true;
  // After start-up segments that moved, the measurement has already mended the heading since
  // the first sample: a restart's correction goes back that far.
  if (moving_startups_ == 0) startup_start_t_s_ = segment_.start_t_s;
  return verdict;
}

SegmentVerdict AutoEstimator::close_segment() {
  SegmentVerdict verdict{.closed = true, .index = segment_index_};
  const double duration_s = segment_.duration_s;
  const bool long_enough = duration_s + kTimeEpsilonS >= settings_.min_segment_s && segment_.stats.count() >= 2;
  verdict.range_ok = long_enough;  // the gate held on every sample of the segment
  if (!long_enough) {
    ++cut_;
    replaced_.quiet_run_over = true;
    previous_.usable = false;
    quiet_.duration_s = 0.0;  // motion: whatever the quiet run was, it has ended
    commit_last_accepted();   // motion came abruptly: the still segment before it stands
    outlier_ = Outlier{};     // and so does a rejection before it
    return verdict;
  }
  const Vec3 mean = segment_.stats.mean_dps();
  models_.assume_white_if_unknown(segment_.stats, duration_s);
  const Vec3& white = models_.white_dps2_s();
  const Vec3 r = white / duration_s;
  SegmentEvidence evidence{
      .mean_dps = mean, .duration_s = duration_s, .white_dps2_s = white, .walk_dps2_per_s = walk_dps2_per_s_};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    evidence.predicted_dps[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_dps();
    evidence.predicted_var[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_variance();
  }
  Judgement judgement = judge_segment(evidence, previous_, settings_);
  // A segment whose rate changed within it is motion starting or stopping, whatever its mean:
  // neither a bias measurement nor a level that could take a restart back.
  const bool rate_changed = rate_changed_within_segment();
  if (!judgement.mean_ok && !rate_changed && replaced_.pending && hint_ == MotionHint::None)
    take_back_recovery(evidence, judgement);
  const bool mean_ok = judgement.mean_ok && !rate_changed;
  const bool same_lean = judgement.same_lean;
  verdict.mean_ok = mean_ok;
  // Only a rejection between two accepted segments (inside a stop) may be taken back: the
  // last segment of a creep has a rejected one before it.
  const bool after_accepted = previous_.usable && previous_accepted_;
  double retracted_weight = 0.0;
  if (!mean_ok && same_lean && hint_ == MotionHint::None && settings_.retract_before_creep) {
    // By the probability that the two segments were a creep (pooled test's figures).
    retracted_weight = settings_.soft_verdicts
                           ? turning_probability(judgement.pooled_deviation_z_dps, judgement.pooled_sd_z_dps)
                           : 1.0;
    retract_last_accepted(retracted_weight);
  } else {
    commit_last_accepted();
  }
  // Kept for the next segment's pooled test, which applies only if no cut comes between.
  previous_.usable = true;
  previous_.mean_dps = mean;
  previous_.duration_s = duration_s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    previous_.predicted_dps[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_dps();
    previous_.predicted_var[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_variance();
  }
  // The vehicle says it stands still while the gyro clearly turns (a turntable, a lift, a
  // wrong hint): the gyro wins, and the conflict is counted for the operator.
  bool hint_conflict = false;
  if (hint_ == MotionHint::Stopped && !mean_ok) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const auto i = static_cast<Eigen::Index>(axis);
      const double sd = std::sqrt(filters_[axis].bias_variance() + r[i]);
      if (std::abs(mean[i] - filters_[axis].bias_dps()) > std::max(kHintConflictDps, kHintConflictSigmas * sd))
        hint_conflict = true;
    }
  }
  if (hint_conflict) ++hint_conflicts_;
  verdict.accepted = hint_ != MotionHint::Moving && (mean_ok || (hint_ == MotionHint::Stopped && !hint_conflict));
  // Counted where the gate alone decided: the mean test passed and nothing else kept it.
  if (rate_changed && judgement.mean_ok && !verdict.accepted) ++rate_changed_segments_;
  const double deviation_z = mean.z() - filters_[2].bias_dps();
  const double sd_z = std::sqrt(filters_[2].bias_variance() + r.z());
  count_verdict(verdict.accepted, mean, previous_.predicted_dps);
  previous_accepted_ = verdict.accepted;
  if (verdict.accepted) {
    reinstate_outlier();
    accept_still(mean, r, segment_.start_t_s + duration_s);
    if (hint_ != MotionHint::Stopped) add_verdict_doubt(deviation_z, sd_z, duration_s, true);
    ++accepted_;
    last_accepted_.pending = true;
    for (std::size_t axis = 0; axis < 3; ++axis) last_accepted_.as_still[axis] = filters_[axis].state();
    quiet_.duration_s = 0.0;
  } else {
    outlier_ = Outlier{};  // a second rejection in a row: the one before was no outlier
    // A rejection inside a stop (between accepted segments) may have been noise: it is taken
    // for still by the probability of that if the next segment is accepted, and only as far
    // as the pair it made with the segment before was not a creep.
    if (settings_.soft_verdicts && after_accepted && hint_ == MotionHint::None && !rate_changed)
      note_outlier((1.0 - turning_probability(deviation_z, sd_z)) * (1.0 - retracted_weight));
    if (hint_ != MotionHint::Moving) add_verdict_doubt(deviation_z, sd_z, duration_s, false);
    ++rejected_;
    if (hint_ == MotionHint::None && settings_.recover_after_s > 0.0) follow_quiet_run(mean);
  }
  return verdict;
}

double AutoEstimator::creep_prior() const {
  return (rejected_weight_ + kPriorSegments * settings_.creep_prior) / (judged_weight_ + kPriorSegments);
}

void AutoEstimator::count_verdict(bool accepted, const Vec3& mean_dps, const Vec3& predicted_dps) {
  judged_weight_ = kVerdictMemory * judged_weight_ + 1.0;
  rejected_weight_ = kVerdictMemory * rejected_weight_ + (accepted ? 0.0 : 1.0);
  if (verdicts_.size() < kVerdictRecords) verdicts_.resize(kVerdictRecords);
  verdicts_[verdicts_counted_ % kVerdictRecords] = {mean_dps, predicted_dps, !accepted};
  ++verdicts_counted_;
}

double AutoEstimator::rejections_at_level(const Vec3& level_dps, std::uint64_t first) const {
  // Nearer in the white noise's own scale on each axis: a vibrating axis counts for little.
  const Vec3 white = models_.white_dps2_s().cwiseMax(std::numeric_limits<double>::min());
  const std::uint64_t oldest = verdicts_counted_ > kVerdictRecords ? verdicts_counted_ - kVerdictRecords : 0;
  double weight = 0.0;
  double decay = 1.0;
  for (std::uint64_t n = first; n > oldest;) {
    --n;
    decay *= kVerdictMemory;
    const VerdictRecord& v = verdicts_[n % kVerdictRecords];
    if (!v.rejected) continue;
    const double to_level = ((v.mean_dps - level_dps).cwiseAbs2().array() / white.array()).sum();
    const double to_bias = ((v.mean_dps - v.predicted_dps).cwiseAbs2().array() / white.array()).sum();
    if (to_level < to_bias) weight += decay;
  }
  return weight;
}

double AutoEstimator::turning_probability(double deviation_dps, double sd_dps) const {
  // Likelihood of the observed deviation if still (Gaussian) and if turning slowly (flat).
  const double z = deviation_dps / sd_dps;
  const double prior = creep_prior();
  const double still = (1.0 - prior) * std::exp(-0.5 * z * z) / (sd_dps * std::sqrt(2.0 * std::numbers::pi));
  // Flat, and not cut off beyond the span: a fast turn must never look still by default.
  const double turning = prior / (2.0 * settings_.creep_span_dps);
  return turning / (still + turning);
}

void AutoEstimator::add_verdict_doubt(double deviation_dps, double sd_dps, double duration_s, bool accepted) {
  const double p_turning = turning_probability(deviation_dps, sd_dps);
  const double p_wrong = accepted ? p_turning : 1.0 - p_turning;
  // The heading's variance takes that of the two-point posterior of the segment's turn.
  const double angle_deg = deviation_dps * duration_s;
  filters_[2].widen_angle(p_wrong * (1.0 - p_wrong) * angle_deg * angle_deg);
}

void AutoEstimator::reinstate_outlier() {
  if (!outlier_.pending) return;
  // The segment before this one is taken for still with the probability it had: the state at
  // this segment's start becomes the mixture of the two verdicts' states, and the state now
  // follows by the same difference carried over this segment (AxisFilter::carry_difference).
  double yaw_change_deg = 0.0;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const AxisFilter::State mixed = blend(outlier_.as_moving[axis], outlier_.as_still[axis], outlier_.weight);
    filters_[axis].carry_difference(mixed, outlier_.as_moving[axis], segment_.duration_s);
    segment_.filters_at_start[axis] = mixed;
    if (axis == 2) yaw_change_deg = mixed.angle_deg - outlier_.as_moving[axis].angle_deg;
  }
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(deg_to_rad(yaw_change_deg), Vec3::UnitZ()));
  segment_.attitude_at_start = turn * segment_.attitude_at_start;
  attitude_.set_attitude(turn * attitude_.attitude());
  outlier_ = Outlier{};
}

void AutoEstimator::note_outlier(double weight) {
  // What taking it for still would have made of the filter, beside what rejecting it made:
  // the angle held over it, the bias only drifting. Its mean does not measure the bias: a
  // segment rejected for its mean is, by that choice, the noise's far tail.
  outlier_.pending = true;
  outlier_.weight = weight;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    outlier_.as_moving[axis] = filters_[axis].state();
    AxisFilter still;
    still.restore(segment_.filters_at_start[axis]);
    still.let_bias_drift(segment_.duration_s, walk_dps2_per_s_);
    still.shift_bias(segment_.temperature_shift_dps[a], segment_.temperature_shift_var[a]);
    outlier_.as_still[axis] = still.state();
  }
}

void AutoEstimator::accept_still(const Vec3& mean_dps, const Vec3& r_dps2, double end_t_s) {
  // Zero-rate update: the platform did not turn during the segment, so take back what was
  // integrated over it, let only the bias drift, then measure the bias with the mean.
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    last_accepted_.as_moving[axis] = filters_[axis].state();
    filters_[axis].restore(segment_.filters_at_start[axis]);
    filters_[axis].let_bias_drift(segment_.duration_s, walk_dps2_per_s_);
    filters_[axis].shift_bias(segment_.temperature_shift_dps[a], segment_.temperature_shift_var[a]);
    filters_[axis].measure_bias(mean_dps[a], r_dps2[a]);
  }
  if (return_correction_deg_ && motion_since_basis_) {
    // A stop after motion agrees with the level a restart returned to: the heading takes the
    // correction held since (its variance was added at the restart).
    AxisFilter::State z = filters_[2].state();
    z.angle_deg += *return_correction_deg_;
    filters_[2].restore(z);
    last_return_correction_deg_ = *return_correction_deg_;
    ++returns_mended_;
    return_correction_deg_.reset();
  }
  history_.measured(end_t_s, filters_[2].bias_dps(), filters_[2].bias_variance(), filters_[2].angle_deg());
  // The attitude goes back to the segment's start, turned about the vertical by the heading
  // correction the bias measurement made to the time before.
  const double yaw_correction_deg = filters_[2].angle_deg() - segment_.filters_at_start[2].angle_deg;
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_correction_deg), Vec3::UnitZ()) * segment_.attitude_at_start);

  last_accepted_.has_temperature = segment_.temp_count > 0;
  if (last_accepted_.has_temperature) {
    last_accepted_.temp_c = segment_.temp_sum_c / segment_.temp_count;
    last_accepted_.mid_t_s = segment_.start_t_s + 0.5 * segment_.duration_s;
    last_accepted_.mean_dps = mean_dps;
    last_accepted_.r_dps2 = r_dps2;
  }
  models_.learn_from_still(segment_.blocks);
  last_accepted_.last_still_before_t_s = last_still_t_s_;
  // Only a stop after motion confirms the start-up level; segments running on from the
  // start-up without a gate trip may be the same turn going on.
  if (motion_since_startup_) bias_from_startup_only_ = false;
  if (motion_since_basis_) bias_confirmed_ = true;
  // A segment agreeing with the restarted level after the quiet run has ended decides for it.
  if (replaced_.quiet_run_over) replaced_.pending = false;
  if (segment_.temp_count > 0) temp_at_still_c_ = segment_.temp_sum_c / segment_.temp_count;
  bias_measured_at(segment_.temp_count > 0 ? temp_at_still_c_ : previous_temp_c_);
  last_still_t_s_ = end_t_s;
}

void AutoEstimator::commit_last_accepted() {
  if (!last_accepted_.pending) return;
  last_accepted_.pending = false;
  if (!last_accepted_.has_temperature) return;
  models_.add_temperature_point(last_accepted_.mid_t_s, last_accepted_.temp_c, last_accepted_.mean_dps,
                                last_accepted_.r_dps2);
}

void AutoEstimator::retract_last_accepted(double weight) {
  if (!last_accepted_.pending) return;
  last_accepted_.pending = false;
  // As if the segment had been judged moving from the start (AxisFilter::carry_difference),
  // by the probability that the two segments were a creep and not noise leaning twice.
  double yaw_change_deg = 0.0;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const double d_angle = filters_[axis].carry_difference(last_accepted_.as_moving[axis],
                                                           last_accepted_.as_still[axis], segment_.duration_s, weight);
    if (axis == 2) yaw_change_deg = d_angle;
  }
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_change_deg), Vec3::UnitZ()) * attitude_.attitude());
  --accepted_;
  ++rejected_;
  ++retracted_;
  last_still_t_s_ = last_accepted_.last_still_before_t_s;
}

void AutoEstimator::follow_quiet_run(const Vec3& mean_dps) {
  const double duration_s = segment_.duration_s;
  bool agrees = quiet_.duration_s > 0.0;
  if (agrees) {
    // The same level within the mean test's own scale: a steady signal, not a changing rate.
    const Vec3 run_mean = quiet_.mean_dps();
    for (Eigen::Index a = 0; a < 3; ++a) {
      const Vec3& white = models_.white_dps2_s();
      const double sd = std::sqrt(white[a] / duration_s + white[a] / quiet_.duration_s);
      agrees = agrees && std::abs(mean_dps[a] - run_mean[a]) <= settings_.k_mean * sd;
    }
  }
  if (!agrees) {
    quiet_ = QuietRun{};
    // The verdicts before this segment: the run's own rejections must not vouch for it.
    quiet_.accepted_before = judged_weight_ - rejected_weight_;
    quiet_.first_verdict = verdicts_counted_ - 1;
    quiet_.filters_at_start = segment_.filters_at_start;
    quiet_.attitude_at_start = segment_.attitude_at_start;
    quiet_.history_at_start = segment_.history_at_start;
  }
  quiet_.duration_s += duration_s;
  quiet_.sum_dps_s += mean_dps * duration_s;
  quiet_.sum_sq_dps2_s += mean_dps.cwiseAbs2() * duration_s;
  quiet_.sigma_dps = segment_.stats.sigma_dps();
  if (segment_.temp_count > 0) quiet_.slope.add(duration_s, segment_.temp_sum_c / segment_.temp_count, mean_dps);
  if (quiet_.duration_s + kTimeEpsilonS < wait_before_recovery_s()) return;
  forget_models_the_run_refutes();
  // Before a stop after motion has confirmed the bias, the run may be the stop and the bias
  // the turn (a start-up while turning); after, only a level the bias could have drifted to.
  // A run that goes on for many times the wait is no creep any more, whatever its level.
  // Nor when most segments lately were rejected at the run's level: a bias (or temperature
  // model) gone wrong rejects the stops, and refusing would lock it in. Counted before the run
  // began (a creep held for minutes rejects its own segments), and only the rejections nearer
  // the run's level than the bias they were judged against, beside the accepted segments:
  // slow motion at other levels says nothing about the bias (counted, it restarted the bias
  // on slow turns after a short start-up; random worlds 24, 91, 173 and held-out 289, 378, 379).
  const double rejected_here = rejections_at_level(quiet_.mean_dps(), quiet_.first_verdict);
  const double judged_here = rejected_here + quiet_.accepted_before;
  const bool mostly_rejecting = rejected_here > kMostlyRejecting * judged_here && judged_here >= kFewVerdicts;
  // A recovery of a bias no stop after motion has confirmed is a choice between two quiet
  // levels that only a later stop can make (see Replaced); one made because most of many
  // verdicts were rejections at the run's level is not (a handful of them says nothing).
  recovery_ambiguous_ = !bias_confirmed_ && !mostly_rejecting;
  if (!bias_confirmed_ || mostly_rejecting || quiet_run_bias_plausible() ||
      quiet_.duration_s >= kUnconditionalRecoveryFactor * settings_.recover_after_s)
    recover_bias();
  else if (quiet_.duration_s < settings_.recover_after_s + duration_s + kTimeEpsilonS)
    ++refused_recoveries_;  // counted once per run; the run goes on and is looked at again
}

void AutoEstimator::forget_models_the_run_refutes() {
  LevelSlope::Fit fit;
  if (!settings_.use_temperature || !quiet_.slope.fit(models_.white_dps2_s(), fit)) return;
  for (int axis = 0; axis < 3; ++axis) {
    const TemperatureModel& model = models_.temperature_model(axis);
    if (!model.ready()) continue;
    const double gap = fit.slope_dps_per_c[axis] - model.slope_dps_per_c(fit.mean_temp_c);
    const double sd =
        std::sqrt(fit.slope_variance[axis] + model.slope_variance() + kSlopeFloorDpsPerC * kSlopeFloorDpsPerC);
    if (std::abs(gap) <= kRefuteSigmas * sd) continue;
    models_.forget_temperature_model(axis);
    ++refuted_models_;
    // The model's slope was off by about `gap` while it was in use, so the angle by gap times the
    // integral of (T - T0) dt since each bias measurement (at T0), summed over the spans between
    // them (model_exposure_c_s_), which the slope's variance never covered: added to the angle's
    // variance, now and at the run's start (where a restart begins). Not
    // to the bias's: that would widen the mean test for the segments to come and let creeps in
    // (tried: four random worlds' max excess grew tenfold). The restart measures the bias anew.
    const auto i = static_cast<std::size_t>(axis);
    const double angle_sd_deg = gap * (model_exposure_c_s_[i] + temp_change_integral_now(i));
    model_exposure_c_s_[i] = 0.0;
    filters_[i].widen_angle(angle_sd_deg * angle_sd_deg);
    quiet_.filters_at_start[i].covariance(0, 0) += angle_sd_deg * angle_sd_deg;
  }
}

double AutoEstimator::run_level_evidence() const {
  // The start-up level or the run's is the bias, the other a steady turn. A zero-rate level is
  // small (zero_rate_sigma_dps) and a turn's rate need not be: the log-likelihood ratio of the
  // two as biases. (A start-up at 18 dps and a stop at -0.5 dps: 40 nats.)
  if (!bias_from_startup_only_) return 0.0;
  const double evidence = (bias_dps().squaredNorm() - quiet_.mean_dps().squaredNorm()) /
                          (2.0 * settings_.zero_rate_sigma_dps * settings_.zero_rate_sigma_dps);
  return std::max(0.0, evidence);
}

double AutoEstimator::wait_before_recovery_s() const {
  // Evidence the wait need not gather: a turn would have to hold a rate near zero to fool it.
  return std::max(segments_.segment_s, settings_.recover_after_s * (1.0 - run_level_evidence() / kWaitEvidence));
}

bool AutoEstimator::quiet_run_bias_plausible() const {
  const Vec3 mean = quiet_.mean_dps();
  const double since_s = std::isfinite(last_still_t_s_) ? std::max(0.0, segment_.start_t_s - last_still_t_s_) : 0.0;
  const double temp_change_c = std::isfinite(temp_at_still_c_) && std::isfinite(previous_temp_c_)
                                   ? std::abs(previous_temp_c_ - temp_at_still_c_)
                                   : 0.0;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    const double walk_sd = std::sqrt(filters_[axis].bias_variance() + walk_dps2_per_s_ * since_s);
    // The filter's bias already follows the temperature model where it is in use: what remains
    // is the model's own slope uncertainty and misfit; without it, the datasheet's bound.
    const TemperatureModel& model = models_.temperature_model(static_cast<int>(axis));
    const double per_c = model.ready() && settings_.use_temperature
                             ? kPlausibleSigmas * std::sqrt(model.slope_variance()) + kModelMisfitDpsPerC
                             : kZeroRateChangeDpsPerC;
    const double bound = kPlausibleSigmas * walk_sd + per_c * temp_change_c + kPlausibleFloorDps;
    if (std::abs(mean[a] - filters_[axis].bias_dps()) > bound) return false;
  }
  return true;
}

AxisFilter::State AutoEstimator::as_if_kept(std::size_t axis, const AxisFilter::State& now, double t_s) const {
  // The filter is linear: what happened since the recovery moved both versions alike, so the
  // mean is the present one plus their difference carried over the time since. Not so the
  // covariance: the quiet run's later segments measured the other level, and their information
  // is not this one's; it is the kept version's, propagated over the time since.
  const double span_s = std::max(0.0, t_s - replaced_.at_t_s);
  AxisFilter filter;
  filter.restore(now);
  filter.carry_difference(replaced_.as_kept[axis], replaced_.as_restarted[axis], span_s);
  AxisFilter kept;
  kept.restore(replaced_.as_kept[axis]);
  AxisFilter::Plain p = kept.plain();
  AxisFilter::propagate(p, 0.0, span_s, models_.white_dps2_s()[static_cast<Eigen::Index>(axis)], walk_dps2_per_s_);
  AxisFilter::State state = filter.state();
  state.covariance << p.p00, p.p01, p.p01, p.p11;
  return state;
}

bool AutoEstimator::take_back_recovery(SegmentEvidence& evidence, Judgement& judgement) {
  replaced_.quiet_run_over = true;
  const double end_t_s = segment_.start_t_s + segment_.duration_s;
  std::array<AxisFilter::State, 3> kept{};
  SegmentEvidence as_kept = evidence;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    kept[axis] = as_if_kept(axis, filters_[axis].state(), end_t_s);
    if (!kept[axis].covariance.allFinite() || !std::isfinite(kept[axis].bias_dps)) return false;
    as_kept.predicted_dps[a] = kept[axis].bias_dps;
    as_kept.predicted_var[a] = kept[axis].covariance(1, 1);
  }
  const Judgement with_kept = judge_segment(as_kept, PreviousSegment{}, settings_);
  if (!with_kept.mean_ok) return false;
  const double yaw_change_deg = kept[2].angle_deg - filters_[2].angle_deg();
  const double start_angle_before_deg = segment_.filters_at_start[2].angle_deg;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    filters_[axis].restore(kept[axis]);
    segment_.filters_at_start[axis] = as_if_kept(axis, segment_.filters_at_start[axis], segment_.start_t_s);
  }
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_change_deg), Vec3::UnitZ()) * attitude_.attitude());
  // The segment's zero-rate update goes back to its start: the attitude there turns alike.
  const double start_yaw_change_deg = segment_.filters_at_start[2].angle_deg - start_angle_before_deg;
  segment_.attitude_at_start =
      Eigen::AngleAxisd(deg_to_rad(start_yaw_change_deg), Vec3::UnitZ()) * segment_.attitude_at_start;
  // Whatever was judged since was judged against the other level, and what it taught the
  // temperature models goes with it: a slope between the two levels is a creep's rate over a
  // few degrees (random world 149: about -0.2 dps/C over 4 C, the bias carried 0.9 dps away).
  commit_last_accepted();
  models_.restore_temperature_models(replaced_.models_kept);
  outlier_ = Outlier{};
  previous_.usable = false;
  replaced_.pending = false;
  return_correction_deg_.reset();
  ++taken_back_;
  evidence = as_kept;
  judgement = with_kept;
  return true;
}

void AutoEstimator::recover_bias() {
  // Taken for a stop: the heading goes back to the run's start (a zero-rate update over it),
  // the bias starts again from the run's mean, and the heading's variance takes the whole
  // bias change over the time it was integrated with the old bias, for which was right is
  // unknown: from the last accepted segment to the run, or from the start when the old bias
  // rests on the start-up alone (that may have been a turn, held as still; then the heading
  // since is integrated again with the new bias, below).
  const Vec3 mean = quiet_.mean_dps();
  // The bias variance: the mean's own noise, plus the spread of the segment means, for a run
  // taken for a stop may still hold some slow motion.
  const Vec3 spread = (quiet_.sum_sq_dps2_s / quiet_.duration_s - mean.cwiseAbs2()).cwiseMax(0.0);
  const Vec3 r = models_.white_dps2_s() / quiet_.duration_s + spread;
  const double run_start_s = segment_.start_t_s + segment_.duration_s - quiet_.duration_s;
  const double trusted_until_s = bias_from_startup_only_          ? startup_start_t_s_
                                 : std::isfinite(last_still_t_s_) ? last_still_t_s_
                                                                  : run_start_s;
  const double exposed_s = std::max(0.0, run_start_s - trusted_until_s);
  replaced_.pending = recovery_ambiguous_;
  replaced_.creep_sized = std::abs(mean.z() - quiet_.filters_at_start[2].bias_dps) <= kFastestCreepDps;
  replaced_.run_s = quiet_.duration_s;
  replaced_.still_s = quiet_.duration_s;
  replaced_.quiet_run_over = false;
  replaced_.at_t_s = segment_.start_t_s + segment_.duration_s;
  double yaw_correction_deg = 0.0;
  // A level a stop measured before (the bias never moved; creeps, a temperature model or a bias
  // set from outside took the estimate away from it): the heading since that stop owes the
  // difference, held until a stop after motion agrees with the level (return_correction_deg_).
  // Not where the start-up's own correction below applies.
  const bool startup_corrected =
      bias_from_startup_only_ && std::abs(mean.z() - quiet_.filters_at_start[2].bias_dps) > kFastestCreepDps;
  const std::optional<double> returned_deg =
      startup_corrected
          ? std::nullopt
          : history_.correction_for_return(mean.z(), r.z(), walk_dps2_per_s_, kReturnSigmas, quiet_.history_at_start,
                                           run_start_s, quiet_.filters_at_start[2].angle_deg);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    replaced_.as_kept[axis] = filters_[axis].state();
    const AxisFilter::State& from = quiet_.filters_at_start[axis];
    // Taken for a stop, the run's own angle left the heading; if it was a creep after all (a
    // choice only a later stop makes), that angle is the error: the variance covers both, when
    // the level is one a creep could have (a faster one held for minutes is a turn).
    const double change_dps = mean[a] - from.bias_dps;
    const double exposed_deg = change_dps * exposed_s;
    const bool creep_sized = std::abs(change_dps) <= kFastestCreepDps;
    const double run_deg = recovery_ambiguous_ && creep_sized ? change_dps * quiet_.duration_s : 0.0;
    // A bias resting on the start-up alone replaced by a level no creep reaches: the start-up
    // was a turn and this the bias all along, so the heading integrated since the start-up
    // takes it too (the start-up's own seconds, held still, included). A creep-sized change
    // may be a creep after a true start-up: no correction, which a take-back would have to
    // undo. The variance keeps the whole change either way.
    AxisFilter::State corrected = from;
    if (bias_from_startup_only_ && !creep_sized) corrected.angle_deg -= exposed_deg;
    const double returned = axis == 2 && returned_deg ? *returned_deg : 0.0;
    if (axis == 2) yaw_correction_deg = corrected.angle_deg - from.angle_deg;
    filters_[axis].restart_bias(corrected, mean[a], r[a],
                                exposed_deg * exposed_deg + run_deg * run_deg + returned * returned);
    replaced_.as_restarted[axis] = filters_[axis].state();
  }
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_correction_deg), Vec3::UnitZ()) * quiet_.attitude_at_start);
  history_.measured(replaced_.at_t_s, mean.z(), r.z(), filters_[2].angle_deg());
  return_correction_deg_ = returned_deg;
  replaced_.models_kept = models_.temperature_models();
  models_.relearn_after_recovery(quiet_.sigma_dps);
  if (bias_from_startup_only_) models_.restart_noise_if_inflated(segment_.stats, segment_.blocks, segment_.duration_s);
  last_still_t_s_ = segment_.start_t_s + segment_.duration_s;
  if (std::isfinite(previous_temp_c_)) temp_at_still_c_ = previous_temp_c_;  // the run was the stop
  bias_measured_at(previous_temp_c_);
  previous_.usable = false;
  quiet_ = QuietRun{};
  outlier_ = Outlier{};
  bias_from_startup_only_ = false;
  // A level the confirmed bias could have drifted to stays confirmed; any other waits for a
  // stop after motion to agree with it (bias_confirmed_ is then already false).
  motion_since_basis_ = false;
  ++recoveries_;
}

HEADINGD_HOT void AutoEstimator::follow_temperature(double temp_c, double t_s) {
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
  temp_change_integral_c_s_.fill(0.0);
  temp_change_t_s_ = previous_t_s_;
}

// One sample: hold still while the start-up segment measures; otherwise close the segment
// when it is full or the range gate trips (judge it, apply the verdict), propagate the filter
// and the attitude with the sample, and report.
const Estimate& AutoEstimator::update(const Sample& sample) {
  estimate_.closed = SegmentVerdict{};
  if (!started_) {
    start(sample);
    return estimate_;
  }
  const double dt_s = sample.t_s - previous_t_s_;
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

void AutoEstimator::start(const Sample& sample) {
  started_ = true;
  if (!std::isfinite(startup_start_t_s_)) startup_start_t_s_ = sample.t_s;
  previous_t_s_ = sample.t_s;
  previous_temp_c_ = sample.temp_c;
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
    const bool trips = !full && range_gate_trips(sample.rate_dps);
    if (!full && !trips) return verdict;
    verdict = close_segment();
    if (trips) {
      previous_.usable = false;  // motion came between
      motion_since_startup_ = true;
      motion_since_basis_ = true;
    }
  }
  ++segment_index_;
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

double AutoEstimator::undecided_offset_deg(double t_s) {
  // A creep held past the wait after a short start-up and a stop after one look alike (the
  // quiet run is the only evidence, and it is the same); the filters follow the restarted
  // level and the sigma covers both, but the heading shown is their probability-weighted mean,
  // which halves the error of whichever was wrong (issue 12's random worlds: seed 200's creep
  // restart, 79 deg -> 46 deg, before the next stop took it back). Even at the wait, as in
  // Replaced; every further second the run holds still makes a creep less likely and a stop
  // more, with odds falling as the square of its length, so a long stop converges on the
  // restart. A faster rate change than a creep's is a turn, not a creep: no share. Only the
  // shown heading and attitude lean (and a heading saved from them); the filters and the tests do not.
  if (!replaced_.pending || !replaced_.creep_sized) return 0.0;
  const double span_s = std::max(0.0, t_s - replaced_.at_t_s);
  if (!replaced_.quiet_run_over) replaced_.still_s = replaced_.run_s + span_s;
  const double odds = std::pow(replaced_.run_s / std::max(replaced_.still_s, replaced_.run_s), kCreepOddsPower);
  const double kept_share = odds / (1.0 + odds);
  const AxisFilter::State& kept = replaced_.as_kept[2];
  const AxisFilter::State& restarted = replaced_.as_restarted[2];
  // The kept version's heading less the restarted one's, carried (as in as_if_kept).
  const double difference_deg = (kept.angle_deg - restarted.angle_deg) - span_s * (kept.bias_dps - restarted.bias_dps);
  return std::isfinite(difference_deg) ? kept_share * difference_deg : 0.0;
}

Vec3 AutoEstimator::bias_dps() const {
  return {filters_[0].bias_dps(), filters_[1].bias_dps(), filters_[2].bias_dps()};
}

void AutoEstimator::fill_estimate(const Sample& sample) {
  const Vec3 bias = bias_dps();
  estimate_.t_s = sample.t_s;
  estimate_.temp_c = sample.temp_c;
  const double undecided_deg = undecided_offset_deg(sample.t_s);
  shown_undecided_deg_ = undecided_deg;
  estimate_.heading_deg = filters_[2].angle_deg() + undecided_deg;
  estimate_.attitude = attitude_.attitude();
  if (undecided_deg != 0.0)
    estimate_.attitude = Eigen::AngleAxisd(deg_to_rad(undecided_deg), Vec3::UnitZ()) * estimate_.attitude;
  estimate_.bias_dps = bias;
  estimate_.rate_dps = sample.rate_dps - bias;
  if (in_startup_ && moving_startups_ == 0) {
    estimate_.heading_sigma_deg = 0.0;  // held by assumption: the platform is still
    estimate_.bias_sigma_dps = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  } else {
    estimate_.heading_sigma_deg = std::sqrt(std::max(0.0, filters_[2].angle_variance()) + scale_variance_deg2());
    for (std::size_t axis = 0; axis < 3; ++axis)
      estimate_.bias_sigma_dps[static_cast<Eigen::Index>(axis)] =
          std::sqrt(std::max(0.0, filters_[axis].bias_variance()));
  }
  estimate_.in_startup = in_startup_;
  estimate_.segment_index = segment_index_;
}

std::size_t AutoEstimator::advance(const Sample* samples, std::size_t count, double until_t_s) {
  if (!started_ || in_startup_) return 0;
  estimate_.closed = SegmentVerdict{};
  // In chunks, each in three passes that together do what update() does sample by sample:
  // the tests and the segment's statistics; the three axis filters, their values held in
  // registers; the attitude. The filters and the attitude take the bias in force at each
  // sample, which only a temperature step moves: a chunk starts with such a step or has none.
  constexpr std::size_t kChunk = 128;
  std::array<double, kChunk> dts;
  std::array<AttitudeIntegrator::Turn, kChunk> turns;
  const Vec3 gate_dps = settings_.k_range * models_.sigma_still_dps();  // the segment under way has samples
  const double gain = scale_.gain();
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
          ((high_with - low_with).array() > gate_dps.array()).any()) {
        special = true;
        break;
      }
      if (n > 0 && models_.follows_temperature(sample.temp_c, previous_temp_c_)) break;  // the next chunk's first
      if (n == 0) follow_temperature(sample.temp_c, sample.t_s);
      previous_temp_c_ = sample.temp_c;
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
      if (std::isfinite(chunk[k].temp_c)) {
        segment_.temp_sum_c += chunk[k].temp_c;
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
  if (taken > 0) fill_estimate(samples[taken - 1]);
  return taken;
}

}  // namespace headingd::core
