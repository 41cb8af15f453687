#pragma once
// headingd's own estimator (method `auto`), built on the paper's segments but testing them
// on the right scale:
//  - a range gate on every sample (cuts a segment the moment motion or vibration starts, so
//    a stop is used from its first second, and stops of min_segment_s count);
//  - a mean test against the Kalman-predicted bias with the mean's own uncertainty, which
//    sees creep of a few hundredths of a dps that the paper's criteria absorb into the bias;
//  - per axis a Kalman filter on (angle, bias): an accepted still segment is a bias
//    measurement and a zero-rate update (the heading integrated over it is taken back);
//  - a bias-versus-temperature model that carries the bias while the platform drives;
//  - honest uncertainty: heading variance from white noise and bias uncertainty.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "core/attitude_integrator.hpp"
#include "core/auto_settings.hpp"
#include "core/axis_filter.hpp"
#include "core/bias_history.hpp"
#include "core/bias_tracker.hpp"
#include "core/estimate.hpp"
#include "core/level_slope.hpp"
#include "core/noise_density.hpp"
#include "core/scale_factor.hpp"
#include "core/segment_judge.hpp"
#include "core/segment_stats.hpp"
#include "core/sensor_models.hpp"
#include "core/stop_innovations.hpp"
#include "core/temperature_model.hpp"
#include "core/temperature_reading.hpp"
#include "core/temperature_trail.hpp"

namespace headingd::core {

class AutoEstimator {
 public:
  // `segments` supplies segment_s, sigma_still_dps and still_at_start.
  AutoEstimator(const BiasSettings& segments, const AutoSettings& settings);

  const Estimate& update(const Sample& sample);
  // The samples from the first on, for as long as none of them is special (the start-up, a
  // sample that closes a segment, one not plausible, one at or after `until_t_s`): the same
  // arithmetic as update(), without an estimate per sample. Returns how many it took; the
  // next one is for update(). last() then describes the last sample taken.
  std::size_t advance(const Sample* samples, std::size_t count, double until_t_s);
  const Estimate& last() const { return estimate_; }

  void set_motion_hint(MotionHint hint) { hint_ = hint; }
  MotionHint motion_hint() const { return hint_; }
  // Segments the vehicle called stopped that the gyro showed turning (the gyro won).
  std::uint64_t hint_conflicts() const { return hint_conflicts_; }
  // The z scale factor, learned from heading fixes (measured = true * (1 + s)).
  const ScaleFactor& scale() const { return scale_; }
  const FixInnovations& fix_innovations() const { return fix_innovations_; }
  // What the variance the filter gathered since the last fix is multiplied by in the sigma
  // shown (1 when calibrate_sigma is off), and how many stops and fixes it rests on.
  double heading_variance_scale() const;
  std::uint64_t stops_weighed() const { return stop_innovations_.stops(); }
  double stop_variance_scale() const { return stop_innovations_.variance_scale(); }
  // Restores a learned scale factor (after a restart); its sigma no wider than configured.
  void restore_scale(double estimate, double sigma) { scale_.restore(estimate, sigma); }
  // Restores a bias (after a restart) with its sigma; ends the start-up phase.
  void set_bias(const Vec3& bias_dps, const Vec3& sigma_dps);
  // The bias just set was saved before the daemon went down: the level may have moved since
  // (a power cycle, a chip replaced), so until a stop or motion has come, a quiet run that the
  // mean test rejects restarts it after one segment, as a start-up without state would measure
  // it (the restored level kept beside, for the next stop to choose), not after the wait.
  // The same start re-measures the noise figures restored with it: its segments run their full
  // length whatever the range gate says until one does not look like motion, which replaces
  // sigma_still where it lies more than 25 % off (a changed rate or bandwidth, another sensor).
  void doubt_restored_level() { restored_level_open_ = noise_check_open_ = true; }
  // The bias just restored held at `saved_c` and was last measured at `measured_c` (NaN:
  // unknown, then nothing is carried). At the first temperature read it follows the change to
  // it as a step while running would: moved by the temperature model where one is in use, its
  // sigma widened by the slope's uncertainty (or the unmodelled bound) over the change since
  // it was measured. Call after the temperature models are restored.
  void carry_restored_bias(double saved_c, double measured_c);
  // The temperature now and the one the bias was last measured at, as the estimator reads
  // them (NaN: unknown, or before the first sample); saved beside the bias.
  double temperature_now_c() const { return started_ ? previous_temp_c_ : std::numeric_limits<double>::quiet_NaN(); }
  double bias_measured_temp_c() const {
    return started_ && std::isfinite(temp_at_bias_c_[2]) ? temp_at_bias_c_[2] : temperature_now_c();
  }
  // Restores the noise figures learned before a restart (unless configured): without them a
  // restart that skips the start-up segment would have no scale for its stillness tests.
  void set_noise(const Vec3& sigma_still_dps, const Vec3& arw_dps_rt_hz) {
    models_.restore_noise(sigma_still_dps, arw_dps_rt_hz);
  }
  // Restores a learned temperature model (after a restart).
  void restore_temperature_model(int axis, const TemperatureModel::Sums& sums, std::uint32_t points) {
    models_.restore_temperature_model(axis, sums, points);
  }
  // A heading fix at a reference point, with its variance. Returns how far the heading moved.
  double set_heading(double heading_deg, double variance_deg2);
  // The heading saved before a restart, with its variance then.
  void restore_heading(double heading_deg, double variance_deg2);

  bool in_startup() const { return in_startup_; }
  const Vec3& sigma_still_dps() const { return models_.sigma_still_dps(); }
  Vec3 noise_density_dps_rt_hz() const { return models_.noise_density_dps_rt_hz(); }
  const TemperatureModel& temperature_model(int axis) const { return models_.temperature_model(axis); }
  std::uint64_t accepted_segments() const { return accepted_; }
  std::uint64_t rejected_segments() const { return rejected_; }  // long enough, failed the mean test
  std::uint64_t cut_segments() const { return cut_; }            // cut by motion before min_segment_s
  // Accepted, then taken back when the next segment showed a creep (counted as rejected).
  std::uint64_t retracted_segments() const { return retracted_; }
  // Times the bias started again from a long quiet period it could not explain (recover_after_s).
  std::uint64_t bias_recoveries() const { return recoveries_; }
  // Of those, a bias restored after a restart that the first still segment refused (0 or 1).
  std::uint64_t saved_bias_restarts() const { return saved_bias_restarts_; }
  // Restored noise figures (sigma_still) the first seconds after a restart replaced (0 or 1).
  std::uint64_t saved_noise_replaced() const { return saved_noise_replaced_; }
  // Start-up segments that looked like motion and were integrated, not taken for the bias.
  int moving_startup_segments() const { return moving_startups_; }
  // Quiet periods that looked like a stop under a wrong bias, whose level the confirmed bias
  // could not have drifted to (a creep or a slow curve held for minutes): no recovery.
  std::uint64_t refused_recoveries() const { return refused_recoveries_; }
  std::uint64_t refuted_temperature_models() const { return refuted_models_; }
  // Of the recoveries, those a line through the rejected stops' levels against temperature
  // explained (TemperatureTrail): the temperature model starts from that line.
  std::uint64_t temperature_trail_restarts() const { return trail_restarts_; }
  double last_trail_slope_z_dps_per_c() const { return last_trail_slope_z_dps_per_c_; }
  std::uint64_t rate_changed_segments() const { return rate_changed_segments_; }
  // Recoveries taken back: a stop agreed with the level the recovery had replaced, and not with
  // its own (the quiet run was a creep after all).
  std::uint64_t recoveries_taken_back() const { return taken_back_; }
  // Restarts that returned to a level a stop had measured before, whose heading correction a
  // later stop after motion confirmed; and the last such correction, deg.
  std::uint64_t returns_mended() const { return returns_mended_; }
  double last_return_correction_deg() const { return last_return_correction_deg_; }
  double last_still_t_s() const { return last_still_t_s_; }
  // Gaps in the samples bridged (below update() in auto_estimator.cpp), and their seconds in all.
  std::uint64_t gaps_bridged() const { return gaps_; }
  double gaps_bridged_s() const { return gaps_s_; }

 private:
  static constexpr double kTimeEpsilonS = 1e-9;  // two times closer than this are one
  // What the wait before a restart is worth, in nats: odds of 20 to 1 that a run held that long is
  // a stop and not a steady turn. A start-up level that much less likely than zero as a zero-rate
  // level is a turn too (startup_level_far_out).
  static constexpr double kWaitEvidence = 3.0;
  struct Segment {
    SegmentStats stats;
    BlockMeans blocks{0.1};
    double duration_s = 0.0;
    double temp_sum_c = 0.0;
    std::uint32_t temp_count = 0;
    double start_t_s = 0.0;
    std::array<AxisFilter::State, 3> filters_at_start{};
    Eigen::Quaterniond attitude_at_start = Eigen::Quaterniond::Identity();
    Vec3 temperature_shift_dps = Vec3::Zero();  // bias moved by the temperature model meanwhile
    Vec3 temperature_shift_var = Vec3::Zero();
    BiasHistory::Mark history_at_start;
  };

  // The steps of update(), in order.
  void start(const Sample& sample);
  bool segment_full(double t_s) const;
  void hold_during_startup(const Sample& sample, double dt_s);
  SegmentVerdict close_segment_if_due(const Sample& sample);
  void propagate(const Sample& sample, double dt_s);
  void propagate_filters(const Sample& sample, double dt_s);
  // The sample's rate as the attitude takes it: bias-corrected, z by the learned scale.
  AttitudeIntegrator::Turn turn_of(const Sample& sample, double dt_s) const;
  void fill_estimate(const Sample& sample);
  // A gap in the samples (below update() in auto_estimator.cpp): whether `dt_s` is one, and the sample after it.
  bool is_gap(double dt_s) const;
  double gap_threshold_s() const;  // infinite until the usual interval is known
  const Estimate& bridge_gap(const Sample& sample, double gap_s);
  void end_runs_at_gap();
  struct GapSide {
    Vec3 rate_dps = Vec3::Zero();
    bool still = false;  // judged so (an accepted segment)
  };
  void integrate_gap(const GapSide& before, const Vec3& after_dps, double gap_s);
  // Every axis's change within the range gate (what a segment's samples may span).
  bool within_gate(const Vec3& change_dps) const;
  // The closing segment's mean sample interval, as the usual one (enough samples only).
  void note_sample_interval();
  double sample_interval_s_ = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t gaps_ = 0;
  double gaps_s_ = 0.0;

  void begin_segment(double t_s);
  void add_to_segment(const Sample& sample, double dt_s);
  bool range_gate_trips(const Vec3& rate_dps) const;
  SegmentVerdict close_startup();
  // The start-up segment's block means scatter like motion, not like a still gyro's noise.
  bool startup_looks_moving() const;
  // The same test on any run of samples: its 0.1 s block means scatter beyond its white noise.
  static bool looks_moving(const SegmentStats& stats, const BlockMeans& blocks, double duration_s);
  // The start-up segment's level lies too far out for a zero-rate level (a steady turn).
  bool startup_level_far_out() const;
  // Whether the segment's block means move with time beyond their noise (kRateChangeSigmas).
  bool rate_changed_within_segment() const;
  SegmentVerdict pass_moving_startup();
  int moving_startups_ = 0;  // start-up segments passed over as motion
  // Every sample while the start-up lasts (at most kMaxMovingStartups + 1 segments), and the
  // attitude before them: once a still start-up has measured the bias, the motion before it is
  // integrated again with it, in 3-D (a yaw turn mends only a level platform).
  std::vector<AttitudeIntegrator::Turn> startup_turns_;  // mean rates over 5 ms
  AttitudeIntegrator::Turn pending_turn_{};              // the block being summed (rate x dt)
  void keep_startup_turn(const Vec3& rate_dps, double dt_s);
  void flush_startup_turn();
  std::size_t startup_turns_before_segment_ = 0;
  Eigen::Quaterniond attitude_at_startup_ = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond startup_attitude_with_bias(const Vec3& bias_dps, std::size_t count) const;
  // Judges a closed segment (segment_judge) and applies the verdict; one `moving` is cut as the
  // range gate cuts (the first after a restart, which the gate did not watch).
  SegmentVerdict close_segment(bool moving = false);
  void accept_still(const Vec3& mean_dps, const Vec3& r_dps2, double t_s);
  void follow_temperature(double temp_c, double t_s);
  // A restored bias follows the change from its saved temperature to the one read now.
  void follow_restored_temperature(double t_s);
  // Whether a temperature model carries the z bias between measurements (BiasHistory).
  bool z_carried_by_model() const { return settings_.use_temperature && models_.temperature_model(2).ready(); }
  // The bias was just measured (or restored) at this temperature: the share of its variance
  // that the temperature's change adds counts from here (NaN: from the next reading).
  void bias_measured_at(double temp_c);
  std::array<double, 3> temp_at_bias_c_{std::numeric_limits<double>::quiet_NaN(),
                                        std::numeric_limits<double>::quiet_NaN(),
                                        std::numeric_limits<double>::quiet_NaN()};
  std::array<double, 3> temp_change_integral_c_s_{};  // of (T - T at the measurement) dt
  double temp_change_t_s_ = 0.0;                      // of the last temperature step followed
  // The integral above summed over the spans between measurements while a temperature model
  // was in use: what a wrong model slope has cost the angle per dps/C (refutation).
  std::array<double, 3> model_exposure_c_s_{};
  double bias_measured_t_s_ = 0.0;  // when bias_measured_at last ran
  double temp_change_integral_now(std::size_t axis) const;
  // Adds the variance of a possibly wrong still/moving verdict (see AutoSettings).
  void add_verdict_doubt(double deviation_dps, double sd_dps, double duration_s, bool accepted);
  // The probability that a segment passing the range gate is a slow turn, learned from the
  // verdicts so far (creep_prior until there are some).
  double creep_prior() const;
  // Posterior probability of a slow turn for a segment mean `deviation_dps` from the predicted
  // bias, with the standard deviation of that difference if still.
  double turning_probability(double deviation_dps, double sd_dps) const;
  // `mean_dps`: the segment's; `predicted_dps`: the bias it was judged against.
  void count_verdict(bool accepted, const Vec3& mean_dps, const Vec3& predicted_dps, double duration_s);
  // The latest verdicts, kept so that a quiet run can ask which of the rejections before it lay
  // at its own level (stops a wrong bias turned away) and not elsewhere (slow motion, which says
  // nothing about the bias): a ring of kVerdictRecords, numbered by verdicts_counted_.
  struct VerdictRecord {
    Vec3 mean_dps = Vec3::Zero();
    Vec3 predicted_dps = Vec3::Zero();
    double duration_s = 0.0;
    bool rejected = false;
  };
  std::vector<VerdictRecord> verdicts_;
  std::uint64_t verdicts_counted_ = 0;
  // The decayed weight (as judged_weight_ counts) of the rejections before verdict `first` whose
  // mean lay nearer `level_dps` than the bias they were judged against; with `agreeing`, only
  // those whose mean also agrees with the level (LevelMatch::Agreeing).
  enum class LevelMatch { Nearer, Agreeing };
  double rejections_at_level(const Vec3& level_dps, std::uint64_t first, LevelMatch match) const;
  bool agrees_with_level(const VerdictRecord& v, const Vec3& level_dps) const;
  // A rejected segment inside a stop, until the next one is judged: the filter states at its
  // end judged moving and judged still, and the probability that it was still (soft_verdicts).
  struct Outlier {
    bool pending = false;
    double weight = 0.0;
    std::array<AxisFilter::State, 3> as_moving{};
    std::array<AxisFilter::State, 3> as_still{};
  };
  void note_outlier(double weight);
  void reinstate_outlier();
  Outlier outlier_;
  bool previous_accepted_ = false;  // the verdict on the segment before (see previous_.usable)
  double judged_weight_ = 0.0;      // segments judged by the mean test, decayed
  double rejected_weight_ = 0.0;    // of them rejected, decayed
  Vec3 bias_dps() const;

  // The last accepted segment, until the next one is judged: the filter states at its end
  // judged moving and judged still, to take the acceptance back (retract_before_creep).
  struct LastAccepted {
    bool pending = false;
    std::array<AxisFilter::State, 3> as_moving{};
    std::array<AxisFilter::State, 3> as_still{};
    bool has_temperature = false;  // its temperature-model point waits for the same verdict
    double mid_t_s = 0.0;
    double temp_c = 0.0;
    Vec3 mean_dps = Vec3::Zero();
    Vec3 r_dps2 = Vec3::Zero();
    double last_still_before_t_s = 0.0;       // last_still_t_s_ before it
    double still_run_start_before_t_s = 0.0;  // still_run_start_t_s_ before it
    double run_start_t_s = 0.0;               // the still run it belongs to
  };
  // `weight`: the probability that it was a creep after all (1: a hard retraction).
  void retract_last_accepted(double weight);
  void commit_last_accepted();

  // Consecutive quiet, rejected segments that agree with one another (recover_after_s).
  struct QuietRun {
    double duration_s = 0.0;
    Vec3 sum_dps_s = Vec3::Zero();      // sum of segment mean times length
    Vec3 sum_sq_dps2_s = Vec3::Zero();  // sum of squared segment mean times length
    std::array<AxisFilter::State, 3> filters_at_start{};
    Eigen::Quaterniond attitude_at_start = Eigen::Quaterniond::Identity();
    Vec3 sigma_dps = Vec3::Zero();    // per-sample sigma of its latest segment
    double accepted_before = 0.0;     // the decayed weight of accepted verdicts before it began
    std::uint64_t first_verdict = 0;  // the number of its first segment's verdict
    BiasHistory::Mark history_at_start;
    LevelSlope slope;                         // its level against temperature
    double temp_sum_c_s = 0.0, temp_s = 0.0;  // its temperature, integrated over the segments that read one
    Vec3 mean_dps() const { return sum_dps_s / duration_s; }
  };
  // Whether the quiet run's level is a bias the sensor could have reached since its last stop
  // (temperature, bias walk): a creep or a slow curve held for minutes is steady enough to pass
  // for a stop under a wrong bias otherwise. Asked only once a stop after motion confirmed it.
  bool quiet_run_bias_plausible() const;
  // How long a quiet run must last before it restarts the bias (recover_after_s, or less
  // against a start-up level far from zero).
  double wait_before_recovery_s() const;
  // Nats for the quiet run's level over the start-up's as the bias (0 once confirmed).
  double run_level_evidence() const;
  // A stop after motion has agreed with the bias since the start-up, restore or recovery it
  // rests on; motion (a range gate trip) has come since that basis.
  bool bias_confirmed_ = false;
  bool motion_since_basis_ = false;
  // A bias restored after a restart, neither agreed with by a stop nor left by motion yet.
  bool restored_level_open_ = false;
  // The first segments after a restart, not cut by the range gate, check the restored noise
  // until one does not look like motion.
  bool noise_check_open_ = false;
  static constexpr double kNoiseMisfit = 1.25;  // sigma_still this far off either way is replaced
  bool noise_recheck_open_ = false;             // a figure raised by it, until the first accepted still segment
  std::uint64_t saved_noise_replaced_ = 0;
  // At such a segment's end: replaces a sigma_still it shows wrong; whether the segment was still
  // (not moving, and within the range gate of the figure now in use).
  bool settle_restored_noise();
  // A restored bias's temperatures until the first temperature read carries it (NaN: none).
  double restored_at_c_ = std::numeric_limits<double>::quiet_NaN();
  double restored_measured_c_ = std::numeric_limits<double>::quiet_NaN();
  double temp_at_still_c_ = std::numeric_limits<double>::quiet_NaN();  // mean of the last accepted
  std::uint64_t refused_recoveries_ = 0;
  // Extends the run with the segment just rejected, or starts it; recovers when it is long.
  void follow_quiet_run(const Vec3& mean_dps);
  // A temperature model whose slope the quiet run's own level contradicts is forgotten: it
  // would otherwise keep the run's stop rejected and its restart refused (the model's narrow
  // slope sd makes the level implausible), and nothing else could ever correct it.
  void forget_models_the_run_refutes();
  std::uint64_t refuted_models_ = 0;
  std::uint64_t rate_changed_segments_ = 0;  // passed the mean test, rejected: the rate changed within them
  void recover_bias();
  QuietRun quiet_;
  // The quiet runs that ended rejected, as stops a drifting bias could have reached, and the
  // restart they explain together with the run under way (TemperatureTrail).
  TemperatureTrail trail_;
  std::uint64_t trail_restarts_ = 0;
  double last_trail_slope_z_dps_per_c_ = 0.0;
  std::optional<TemperatureTrail::Line> trail_line_;  // set while recover_bias acts on it
  void end_quiet_run();
  bool level_within_datasheet_drift() const;
  bool restart_on_temperature_trail();
  bool line_meets_measured_level(const TemperatureTrail::Line& line) const;
  // What a recovery of a bias no stop had confirmed replaced, until a stop decides between the
  // two levels: the filters at the recovery as they were without it (the quiet run integrated
  // as motion) and just after it. Nothing in the quiet run tells a stop from a creep held as
  // long after a short start-up; the next stop does.
  struct Replaced {
    bool pending = false;
    // The heading shown leans towards the kept level while undecided: not where rejections
    // near the restarted level (if not at it) have made the restart the likelier choice.
    bool lean = false;
    bool from_restore = false;    // it replaced a restored level at the first segment (no lean)
    bool quiet_run_over = false;  // a cut or a rejected segment has come since the recovery
    double at_t_s = 0.0;
    std::array<AxisFilter::State, 3> as_kept{};
    std::array<AxisFilter::State, 3> as_restarted{};
    bool creep_sized = false;                     // the z level changed by no more than a creep's rate
    double run_s = 0.0;                           // the quiet run's length at the recovery
    double still_s = 0.0;                         // its length with the still time after the recovery, until motion
    SensorModels::TemperatureModels models_kept;  // the temperature models the recovery started over
    // What the kept version's temperature share grows from (add_kept_temperature_share):
    std::array<double, 3> kept_temp_at_bias_c{};     // T where the kept version measured its bias
    std::array<double, 3> kept_temp_integral_c_s{};  // integral of (T - that T) dt, up to the recovery
    double temp_at_c = 0.0;                          // T at the recovery
    double warmed_c_s = 0.0;                         // integral of (T - temp_at_c) dt since the recovery
    double warmed_t_s = 0.0;                         // when warmed_c_s was last summed
  };
  Replaced replaced_;
  // The heading shown while a creep-sized recovery is undecided leans towards the kept level by
  // that level's probability; the filters keep the restarted one (see fill_estimate).
  double undecided_offset_deg(double t_s);
  // The kept version's heading less the restarted one's at t_s (and the still time so far).
  double kept_difference_deg(double t_s);
  // What a restored level replaced without a lean adds to the shown heading's variance.
  double restored_level_doubt_deg2(double t_s);
  double shown_undecided_deg_ = 0.0;  // in the estimate last filled
  bool recovery_ambiguous_ = false;   // the recovery under way replaces an unconfirmed bias
  bool recovery_revocable_ = false;   // a later stop may still take it back (ambiguous or not)
  std::uint64_t taken_back_ = 0;
  std::uint64_t saved_bias_restarts_ = 0;
  // For a segment the mean test rejected: if it agrees with the replaced level, puts that level
  // back (the filters now and at the segment's start, the attitude's yaw) and re-judges.
  bool take_back_recovery(SegmentEvidence& evidence, Judgement& judgement);
  // A filter state `now` (at time `t_s`) as it would be had the recovery not happened.
  AxisFilter::State as_if_kept(std::size_t axis, const AxisFilter::State& now, double t_s) const;
  // The temperature's share the kept version's covariance gathers over `span_s` after the recovery.
  void add_kept_temperature_share(std::size_t axis, double span_s, AxisFilter::Plain& p) const;
  // The odds that an undecided recovery's quiet run was a creep, against a stop.
  double creep_odds() const;
  // The bias still rests on the start-up segment alone (and segments running on from it).
  bool bias_from_startup_only_ = false;
  double startup_start_t_s_ = std::numeric_limits<double>::quiet_NaN();  // or the first sample's
  bool motion_since_startup_ = false;  // the range gate has tripped since the start-up

  BiasSettings segments_;
  PreviousSegment previous_;
  LastAccepted last_accepted_;
  AutoSettings settings_;
  std::array<AxisFilter, 3> filters_{};
  double turned_from_deg_ = 0.0;                  // the heading at start, restore or the last fix
  Vec3 vertical_turned_from_deg_ = Vec3::Zero();  // the attitude's vertical turns then
  ScaleFactor scale_;
  // The scale factors' share of the heading variance since the last fix: z's (learned from
  // fixes) times the filter's net turn, and x's and y's (as configured) times the turns they
  // made about the vertical.
  double scale_variance_deg2() const;
  // Turning counts from here (start, restore, a fix).
  void count_turns_from_here() {
    turned_from_deg_ = filters_[2].angle_deg();
    vertical_turned_from_deg_ = attitude_.vertical_turn_deg();
  }
  // The heading variance shown: the filter's, the part since the last fix or restore scaled by
  // what the stops and the fixes have shown of it (settings_.calibrate_sigma), and the scale
  // factor's share.
  double shown_heading_variance_deg2() const;
  // A fix with a variance, within kFixGateSigmas of the heading shown: a measurement of it.
  bool fix_within_gate(double innovation_deg, double fix_variance_deg2) const;
  // A heading fix's innovation against the sigma shown, before the fix is applied.
  void note_fix_innovation(double innovation_deg, double fix_variance_deg2);
  StopInnovations stop_innovations_;
  FixInnovations fix_innovations_;
  double fixed_angle_variance_deg2_ = 0.0;  // the angle's variance just after the last fix or restore
  double rate_for_angle(const Vec3& rate_dps, int axis) const;
  // The z rate the filter integrates: its turn (rate - bias) by the learned scale's gain.
  static double scaled_z(double rate_dps, double bias_dps, double gain) {
    return gain == 1.0 ? rate_dps : bias_dps + (rate_dps - bias_dps) * gain;
  }
  SensorModels models_;
  BiasHistory history_;  // the z levels stops measured, for a restart that returns to one
  // The heading correction of a restart that returned to an earlier level, until a stop after
  // motion agrees with that level (a creep held for minutes can match an old level by chance).
  std::optional<double> return_correction_deg_;
  std::uint64_t returns_mended_ = 0;
  double last_return_correction_deg_ = 0.0;
  AttitudeIntegrator attitude_;
  Segment segment_;
  Estimate estimate_;
  MotionHint hint_ = MotionHint::None;
  std::uint64_t hint_conflicts_ = 0;

  double walk_dps2_per_s_ = 0.0;  // q
  bool started_ = false;
  bool in_startup_ = true;
  double previous_t_s_ = 0.0;
  double previous_temp_c_ = 0.0;  // as the estimator reads it (TemperatureReading)
  TemperatureReading temperature_reading_;
  double reported_temp_c_ = 0.0;  // the sample's own, for the estimate
  std::uint64_t segment_index_ = 0;
  std::uint64_t accepted_ = 0;
  std::uint64_t rejected_ = 0;
  std::uint64_t cut_ = 0;
  std::uint64_t retracted_ = 0;
  std::uint64_t recoveries_ = 0;
  double last_still_t_s_ = std::numeric_limits<double>::quiet_NaN();  // NaN until a segment is accepted
  // Where the run of back-to-back accepted segments that ends at last_still_t_s_ began.
  double still_run_start_t_s_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace headingd::core
