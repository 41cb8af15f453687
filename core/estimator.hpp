#pragma once
// One sample in, one estimate out, whichever method is configured: the paper's A/B/C or
// headingd's own `auto` (the default).
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "core/auto_estimator.hpp"
#include "core/diagnostics.hpp"
#include "core/paper_estimator.hpp"

namespace headingd::core {

struct EstimatorSettings {
  Method method = Method::Auto;
  BiasSettings segments = kDefaultBiasSettings;  // segment length, sigma_still, start-up; A/B/C criteria
  AutoSettings automatic = kDefaultAutoSettings;
};

inline const EstimatorSettings kDefaultEstimatorSettings{};

// Empty when usable; otherwise names the offending field and why.
std::optional<std::string> validate(const EstimatorSettings& settings);
// Empty when a saved state may be restored; otherwise what is out of range.
std::optional<std::string> implausible(const LearnedState& state);
// The state as it may be saved: a bias sigma beyond the restore limit capped to it.
LearnedState savable(LearnedState state);

class Estimator {
 public:
  explicit Estimator(const EstimatorSettings& settings = kDefaultEstimatorSettings);

  const Estimate& update(const Sample& sample);
  // Samples whose estimates nobody needs (those before `until_t_s`), from the first on, for as
  // long as none is special (AutoEstimator::advance): the state moves exactly as update()
  // moves it. Returns how many it took, 0 when the next one is for update() (the paper's
  // methods, always); last() then describes the last one taken. The output invariant is
  // checked once, at the end: a fault freezes the estimate at the last finite one checked.
  std::size_t advance(const Sample* samples, std::size_t count, double until_t_s);
  // The state went non-finite: the estimate is frozen with an infinite sigma (Estimate::fault).
  bool fault() const { return fault_; }
  const Estimate& last() const;
  std::uint64_t samples() const { return samples_; }

  Method method() const { return settings_.method; }
  const EstimatorSettings& settings() const { return settings_; }
  std::uint64_t accepted_segments() const;
  std::uint64_t rejected_segments() const;
  Vec3 sigma_still_dps() const;
  bool in_startup() const;

  // Everything a sink may want to report, as one value.
  Diagnostics diagnostics() const;
  // What a restart should start from (the state file), and taking it back. Before the first
  // sample: what was restored, as it was restored (or nothing learned, if nothing was).
  LearnedState learned() const;
  // `with_heading`: also the heading saved with it (a vehicle that was not moved meanwhile).
  // Throws std::invalid_argument, restoring nothing, for a state with non-finite or absurd values.
  void restore(const LearnedState& state, bool with_heading = true);
  // The same for a state saved before the daemon went down (the state file): the bias's sigma
  // widened by restart_bias_sigma_dps for what the time down moved. restore() alone is for a
  // state handed over while running (a configuration reload).
  void restore_after_restart(const LearnedState& state, bool with_heading = true);

  void set_motion_hint(MotionHint hint);
  // Restores a bias with its sigma (after a restart): no calibration stop needed.
  void restore_bias(const Vec3& bias_dps, const Vec3& sigma_dps);
  AutoEstimator* automatic_mutable() { return std::get_if<AutoEstimator>(&impl_); }
  void set_heading(double heading_deg, double variance_deg2);
  // The auto estimator, when it is the method in force (for its model and noise figures).
  const AutoEstimator* automatic() const { return std::get_if<AutoEstimator>(&impl_); }

 private:
  EstimatorSettings settings_;
  std::variant<PaperEstimator, AutoEstimator> impl_;
  const Estimate& enter_fault(const Estimate& poisoned);
  // Checks the estimate on the way out: the fault if it is not finite, else kept as good.
  const Estimate& checked(const Estimate& e);
  LearnedState learned_now() const;

  std::uint64_t samples_ = 0;
  // The output invariant: what leaves update() is finite, or a fault (sigma infinite).
  bool fault_ = false;
  Estimate fault_estimate_;
  double good_heading_deg_ = 0.0;
  Eigen::Quaterniond good_attitude_ = Eigen::Quaterniond::Identity();
  Vec3 good_bias_dps_ = Vec3::Zero();
  LearnedState good_state_;  // at the last segment closed while healthy: what a fault saves
  // What restore() was given: before the first sample it is all there is to hand on (the
  // estimates describe no sample yet; saving them wrote a zero bias over the state file).
  std::optional<LearnedState> restored_;
  std::uint64_t heading_fixes_ = 0;
  double heading_fix_offset_deg_ = 0.0;
};

}  // namespace headingd::core
