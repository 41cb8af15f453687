#pragma once
// The auto estimator's verdict on a closed segment, as a pure function of what the segment
// measured and what the filter predicted: no state is changed here.
//  - mean test: |mean - predicted bias| <= k_mean * sqrt(P + N^2/T) on every axis;
//  - pooled test: the same over this segment and the one before it (no cut between), against
//    the bias predicted before both, which sees creep too slow for one segment;
//  - same lean: this segment alone fails against the bias predicted before the one before,
//    and that one leaned the same way by at least a sigma of its own: a creep that started
//    inside the earlier segment, whose acceptance should be taken back.
#include "core/auto_settings.hpp"
#include "core/sample.hpp"

namespace headingd::core {

// The segment before, kept for the pooled test and the lean.
struct PreviousSegment {
  bool usable = false;  // long enough, and this segment follows it without a cut
  Vec3 mean_dps = Vec3::Zero();
  double duration_s = 0.0;
  Vec3 predicted_dps = Vec3::Zero();  // bias predicted before it was judged
  Vec3 predicted_var = Vec3::Zero();
};

struct SegmentEvidence {
  Vec3 mean_dps = Vec3::Zero();
  double duration_s = 0.0;
  Vec3 predicted_dps = Vec3::Zero();  // the filter's bias before this segment's verdict
  Vec3 predicted_var = Vec3::Zero();
  Vec3 white_dps2_s = Vec3::Zero();  // N^2 per axis
  double walk_dps2_per_s = 0.0;      // q
};

struct Judgement {
  bool mean_ok = false;    // the mean (and pooled) test passed on every axis
  bool same_lean = false;  // a creep leaning the way the previous segment leaned
  // The pooled test on z (when the previous segment is usable): the two segments' mean less
  // the bias predicted before both, and that difference's sigma if still.
  double pooled_deviation_z_dps = 0.0;
  double pooled_sd_z_dps = 0.0;
};

Judgement judge_segment(const SegmentEvidence& segment, const PreviousSegment& previous, const AutoSettings& settings);

}  // namespace headingd::core
