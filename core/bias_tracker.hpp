#pragma once
// Tracks the gyro bias from the segments in which the platform stands still
// (docs/algorithm.md). Cuts time into segments of segment_s, judges each closed segment
// with the method's criteria and, when it is accepted, takes its mean as the new bias.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "core/estimate.hpp"
#include "core/method.hpp"
#include "core/segment_stats.hpp"
#include "core/stillness.hpp"

namespace headingd::core {

struct BiasSettings {
  double segment_s = 3.0;    // segment length, s (paper: 3 s)
  double k_range = 7.0;      // range criterion factor (paper: 7)
  double k_mean = 1.0;       // mean-consistency factor (paper: 1)
  std::size_t n_means = 10;  // accepted means in the moving average (ours: 30 s of stops)
  // Per-sample noise sigma of a still sensor, dps. Unset: measured from the start-up segment.
  std::optional<Vec3> sigma_still_dps;
  // The platform stands still for the first segment: its mean is the initial bias and,
  // unless configured, its sigma is sigma_still. Heading is held while it lasts.
  bool still_at_start = true;
};

inline const BiasSettings kDefaultBiasSettings{};

// Empty when the settings are usable; otherwise names the offending field and why.
std::optional<std::string> validate(const BiasSettings& settings);

class BiasTracker {
 public:
  explicit BiasTracker(Method method = Method::C, const BiasSettings& settings = kDefaultBiasSettings);

  // Closes the running segment when this sample lies past its end (judging it before the
  // sample is used, so the new bias applies to this sample), then adds the sample.
  SegmentVerdict update(const Sample& sample);

  const Vec3& bias_dps() const { return bias_dps_; }
  // Restores a bias (after a restart): used at once, and seeds the mean history.
  void set_bias(const Vec3& bias_dps);

  bool in_startup() const { return in_startup_; }
  const Vec3& sigma_still_dps() const { return sigma_still_dps_; }
  std::uint64_t segment_index() const { return segment_index_; }
  std::uint64_t accepted_segments() const { return accepted_; }
  std::uint64_t rejected_segments() const { return rejected_; }
  const BiasSettings& settings() const { return settings_; }
  Method method() const { return method_; }

 private:
  SegmentVerdict close_segment();
  SegmentVerdict close_startup_segment();

  Method method_;
  BiasSettings settings_;
  SegmentStats segment_;
  MeanHistory history_;
  Vec3 bias_dps_ = Vec3::Zero();
  Vec3 sigma_still_dps_ = Vec3::Zero();
  double segment_start_s_ = 0.0;
  bool started_ = false;
  bool in_startup_ = false;
  std::uint64_t segment_index_ = 0;
  std::uint64_t accepted_ = 0;
  std::uint64_t rejected_ = 0;
};

}  // namespace headingd::core
