#pragma once
// The z gyro's scale factor, measured = true * (1 + s). Unknown, it is an error of s times the
// net angle turned, the same on every sample (not process noise): the heading variance adds
// variance(s) * turned^2. A heading fix after a turn measures it: one Kalman step on s, after
// which the turn is integrated corrected (gain() = 1 / (1 + estimate)) and its variance smaller.

namespace headingd::core {

// Beyond the datasheet's +-2 % (a larger one says a fix carried an error of another cause).
inline constexpr double kMaxLearnedScale = 0.05;

class ScaleFactor {
 public:
  explicit ScaleFactor(double sigma = 0.0) : variance_(sigma * sigma), configured_variance_(sigma * sigma) {}

  // A heading fix: `innovation_deg` = fix - heading, after a net `turned_deg` since the last
  // fix, against the angle's own variance and the fix's.
  void learn(double innovation_deg, double turned_deg, double angle_variance_deg2, double fix_variance_deg2);
  // A learned value saved before a restart; its sigma no wider than configured.
  void restore(double estimate, double sigma);

  double heading_variance_deg2(double turned_deg) const { return variance_ * turned_deg * turned_deg; }
  double estimate() const { return estimate_; }
  double sigma() const;
  double gain() const { return gain_; }
  bool learned() const { return learned_; }

 private:
  double estimate_ = 0.0;
  double variance_ = 0.0;
  double configured_variance_ = 0.0;
  double gain_ = 1.0;
  bool learned_ = false;
};

}  // namespace headingd::core
