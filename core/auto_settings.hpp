#pragma once
// Settings of headingd's own estimator, method `auto` (see auto_estimator.hpp).
#include <optional>

#include "core/sample.hpp"
#include "core/temperature_model.hpp"

namespace headingd::core {

struct AutoSettings {
  // Shortest still period that counts, s: a stop interrupted by motion after this long is
  // still used (the paper's fixed 3 s grid wastes most short stops).
  double min_segment_s = 1.0;
  // Range gate, checked on every sample against k_range * sigma_still: the fast first test
  // that cuts a segment the moment the platform moves or vibrates. Looser than the paper's 7,
  // which rejects about half of truly still 3 s segments on three axes.
  double k_range = 10.0;
  // Mean test: a segment is still when |mean - predicted bias| <= k_mean * sqrt(P + N^2/T) on
  // every axis (P: bias variance, N: white-noise density, T: segment length). The mean of a
  // still 3 s segment has a sigma of about N/sqrt(3 s) ~ 0.006 dps, so creep of a few
  // hundredths of a dps stands out.
  double k_mean = 3.5;
  // The same test on the mean of this segment and the one before it (when no motion came
  // between), against the bias predicted before both: catches creep too slow for one segment.
  double k_mean_pooled = 3.5;
  // Angle random walk per axis, dps/sqrt(Hz) (`headingd allan --emit-config`). Unset: measured
  // from the start-up segment's block means, then refined from every accepted segment.
  std::optional<Vec3> arw_dps_rt_hz;
  // Bias random walk, dps/sqrt(s): how fast the bias may wander between still segments
  // (the Kalman process noise). Default: a bias instability of ~3.6 deg/h reached in ~100 s.
  double bias_walk_dps_rt_s = 1e-4;
  double block_s = 0.1;  // block length of the noise-density estimate, s
  // Scale-factor uncertainty, 1 sigma as a fraction of the rate. A scale error s makes a
  // heading error of s times the net angle turned, the same on every sample (so it is not
  // process noise): the heading sigma adds sigma_s * |turned since the last fix or start|.
  // Default 1 %: the L3GD20H datasheet (Table 3) gives +-2 % sensitivity change over
  // -40..+85 C, taken here as 2 sigma; a calibrated sensor may set its own figure.
  double scale_factor_sigma = 0.01;
  // true: the heading sigma is calibrated by the run's own stops — the part gathered since the
  // last fix widened by how far the bias moved between measurements against how far the filter
  // predicted (core/stop_innovations.hpp; never narrowed). The estimates do not depend on it;
  // false: the filter's own.
  bool calibrate_sigma = true;
  // What the stillness test cannot tell apart: a segment whose mean is near the threshold may
  // hide a slow turn (if accepted) or be still after all (if rejected). The probability p of
  // the other verdict comes from a two-hypothesis mixture: still (Gaussian around the
  // predicted bias) against turning slowly (rates spread evenly over +-creep_span_dps, prior:
  // how often segments were rejected so far, creep_prior until there are some). The heading
  // variance grows by p (1 - p) (deviation * T)^2.
  // true (soft verdicts): a rejection inside a stop (accepted segments either side) is taken
  // for still by its probability of that, and a retraction (retract_before_creep) by the
  // probability that the two segments were a creep; the filter takes the mixture of the two
  // verdicts' states. false: the hard verdicts decide.
  bool soft_verdicts = true;
  double creep_span_dps = 0.2;
  // A creep that starts inside a segment can pass that segment's tests and then fail the next
  // one's (the pooled test sees it). true: the next segment's rejection takes the first
  // one's acceptance back, exactly as if it had been judged moving from the start, so the
  // bias does not keep a piece of the creep.
  bool retract_before_creep = true;
  double retract_min_lean = 1.0;   // the first segment's own lean, in sigmas of its mean
  double retract_next_lean = 2.0;  // the next segment's lean on its own, in sigmas of its mean
  // A start-up while the platform turned (no saved state) takes the turn rate for the bias,
  // and every later stop then fails the mean test against it. A quiet period (no gate trip)
  // whose segments all fail the test yet agree with one another for this long is taken for
  // a stop under a wrong bias, and the bias starts again from it. Longer than any steady
  // creep or turntable run without vibration we expect; 0 turns it off.
  double recover_after_s = 90.0;
  // How far from zero the chip's zero-rate level may lie, 1 sigma, dps: the bias's prior when
  // nothing is known, and what makes a start-up level far out (a turn, taken for still) give way
  // to a stop before recover_after_s. 2: a few dps, an L3GD20H at 245 dps full scale in
  // practice (the datasheet states +-25 dps at 2000 dps only); chips with a wider zero-rate
  // tolerance set their own.
  double zero_rate_sigma_dps = 2.0;
  // How far the zero-rate level may move while the daemon is down (a power cycle, the board's
  // stress changing: datasheet section 2.6.2 warns that mounting stress shifts it), 1 sigma,
  // dps: added to a restored bias's sigma, so that the first stops measure a shifted bias rather
  // than be rejected against a sigma learned while running. The datasheet gives no turn-on
  // repeatability; 0.02 keeps a restart no worse than a start without state for shifts up to
  // 0.05 dps (AutoEstimator.ARestoredBiasLeavesRoomForWhatTheTimeDownMoved), and far narrower than the prior.
  double restart_bias_sigma_dps = 0.02;
  double creep_prior = 0.1;
  // Time constant of the running estimate of sample-to-sample noise (vibration), s: while it
  // exceeds the still noise, the heading variance grows with it instead.
  double vibration_tau_s = 1.0;
  bool use_temperature = true;
  // How far the bias may move per degree C where no temperature model carries it (before the
  // model has learned, or with use_temperature off), 1 sigma, dps/C. The bias variance grows
  // by (this x the temperature change since the bias was measured)^2; with the model in use,
  // by its own slope variance x that change^2.
  double unmodelled_bias_per_c_dps = 0.003;
  TemperatureModelSettings temperature = kDefaultTemperatureModelSettings;
};

inline const AutoSettings kDefaultAutoSettings{};

}  // namespace headingd::core
