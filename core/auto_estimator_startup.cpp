// AutoEstimator: the start-up segment, and a start-up while the platform moves (its turn is
// kept and integrated again once a still start-up has measured the bias).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/auto_estimator.hpp"
#include "core/units.hpp"

namespace headingd::core {
namespace {

// A start-up segment whose block means scatter this many times more than its samples' white
// noise allows is motion; after this many of them (5 minutes) the next is the start-up whatever
// it looks like (a platform vibrating slowly where it stands would otherwise never start). Not
// fewer: a vehicle or a hand may move for minutes before its first stop (BROAD's tapping and
// vibration trials move for two, and a start-up forced inside that was a wrong bias).
constexpr double kMovingStartupRatio = 15.0;
constexpr int kMaxMovingStartups = 100;
constexpr double kStartupTurnS = 0.005;  // the start-up's samples are kept this long at a time
// A start-up level more than kWaitEvidence unlikely as a zero-rate level (in nats against zero,
// under the prior of zero_rate_sigma_dps) is a steady turn: the platform started inside one. Integrated as motion on
// the prior, its heading stays within the prior's few dps of the truth instead of standing still while the platform
// turns (issue 12's random worlds 19, 43, 75: 18, 12 and 10 dps turns of 13-17 s at start, 361, 187 and 167 deg shown
// before the first stop mended them). For at most this many segments (30 s): a chip whose level
// truly lies that far out (a zero_rate_sigma_dps set too narrow) starts then, and the first stop
// restarts the bias as before (a level far from zero gives way at once).
constexpr int kMaxFarOutStartups = 10;

}  // namespace

bool AutoEstimator::startup_looks_moving() const {
  return looks_moving(segment_.stats, segment_.blocks, segment_.duration_s);
}

bool AutoEstimator::looks_moving(const SegmentStats& stats, const BlockMeans& blocks, double duration_s) {
  // Still, the 0.1 s block means scatter as the white noise allows (the chip's low-pass can
  // make that a few times the samples' own variance at high rates); a hand or a vehicle
  // turning moves them by the motion, tens of times more (BROAD's rotations: 20-29).
  NoiseDensity blocks_only;
  blocks_only.add(blocks);
  if (!blocks_only.known() || stats.count() < 2) return false;
  const double dt_s = duration_s / static_cast<double>(stats.count());
  const Vec3 from_samples = stats.sigma_dps().cwiseAbs2() * dt_s;
  return (blocks_only.density_squared().array() > kMovingStartupRatio * from_samples.array()).any();
}

bool AutoEstimator::startup_level_far_out() const {
  if (moving_startups_ >= kMaxFarOutStartups) return false;
  const double sigma = settings_.zero_rate_sigma_dps;
  // Any 0.1 s block that far out: a turn that ends inside the segment leaves its mean near a
  // plausible level, and the segment is no measurement of it (random world 464: 0.6 s of a 9 dps
  // turn in a start-up, a bias 2 dps off).
  return segment_.blocks.largest_squared_level() / (2.0 * sigma * sigma) > kWaitEvidence;
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
  // The held segment's turns, through the attitude itself (not a copy, as a start-up's
  // re-integration with the bias measured later is): its turns about the vertical count.
  attitude_.set_attitude(attitude_at_startup_);
  attitude_.add_all(startup_turns_.data(), startup_turns_.size());
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
  if (moving_startups_ < kMaxMovingStartups && (startup_looks_moving() || startup_level_far_out()))
    return pass_moving_startup();
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
                                  stats.mean_dps(), r, segment_.start_t_s);
  }
  ++accepted_;
  last_still_t_s_ = segment_.start_t_s + duration_s;
  still_run_start_t_s_ = segment_.start_t_s;
  history_.measured(last_still_t_s_, filters_[2].bias_dps(), filters_[2].bias_variance(), filters_[2].angle_deg(),
                    false, duration_s);
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

}  // namespace headingd::core
