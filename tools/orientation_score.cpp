#include "tools/orientation_score.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/units.hpp"
#include "tools/csv_table.hpp"

namespace headingd::app {
namespace {

using Quat = Eigen::Quaterniond;

constexpr double kSameTimeS = 1e-6;  // rows written with microseconds (or finer) meet within this

struct QuatSeries {
  std::vector<double> t_s;
  std::vector<Quat> q;
  std::vector<bool> valid;
};

QuatSeries quaternions(const std::vector<std::vector<double>>& columns) {
  QuatSeries series;
  series.t_s = columns[0];
  for (std::size_t i = 0; i < series.t_s.size(); ++i) {
    const Quat q(columns[1][i], columns[2][i], columns[3][i], columns[4][i]);
    const bool valid = q.coeffs().allFinite() && q.norm() > 0.5;  // lost tracking, or not a rotation
    series.q.push_back(valid ? q.normalized() : Quat::Identity());
    series.valid.push_back(valid);
  }
  return series;
}

// The truth's columns: BROAD's (and ours) by default, or EuRoC/ASL ground truth's
// (state_groundtruth_estimate0/data.csv: "#timestamp [ns]", the orientation of the IMU's frame S
// in the room's frame R as q_RS_w, q_RS_x, …), whose time is in nanoseconds.
struct TruthLayout {
  std::vector<std::string> columns;  // time, w, x, y, z
  double seconds_per_unit = 1.0;
  bool comment_header = false;
};

constexpr const char* kEurocBias[3] = {"b_w_RS_S_x", "b_w_RS_S_y", "b_w_RS_S_z"};

std::optional<TruthLayout> layout_of(const std::vector<std::string>& names) {
  const auto has = [&](const char* name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  if (has("time_s") && has("qw") && has("qx") && has("qy") && has("qz"))
    return TruthLayout{{"time_s", "qw", "qx", "qy", "qz"}, 1.0, false};
  if (has("timestamp") && has("q_RS_w") && has("q_RS_x") && has("q_RS_y") && has("q_RS_z"))
    return TruthLayout{{"timestamp", "q_RS_w", "q_RS_x", "q_RS_y", "q_RS_z"}, 1e-9, true};
  return std::nullopt;
}

}  // namespace

bool is_orientation_truth(const std::string& truth_path) { return layout_of(header_columns(truth_path)).has_value(); }

double heading_twist_deg(const Quat& truth, const Quat& estimate) {
  const Quat e = truth * estimate.inverse();
  return core::rad_to_deg(std::remainder(2.0 * std::atan2(e.z(), e.w()), 2.0 * M_PI));
}

OrientationScore score_orientation(const std::string& estimates_path, const std::string& truth_path,
                                   double max_truth_gap_s) {
  OrientationScore score;
  const auto truth_names = header_columns(truth_path);
  const auto layout = layout_of(truth_names);
  if (!layout) return score;  // not an orientation truth: nothing to score
  score.has_moving = std::find(truth_names.begin(), truth_names.end(), "moving") != truth_names.end();
  TableOptions nan_allowed;
  nan_allowed.nan_text_is_nan = true;
  nan_allowed.empty_is_nan = true;
  TableOptions truth_options = nan_allowed;
  truth_options.comment_header = layout->comment_header;
  score.has_bias =
      layout->comment_header && std::all_of(std::begin(kEurocBias), std::end(kEurocBias), [&](const char* b) {
        return std::find(truth_names.begin(), truth_names.end(), b) != truth_names.end();
      });
  std::vector<std::string> wanted = layout->columns;
  if (score.has_moving) wanted.emplace_back("moving");
  const std::size_t bias_column = wanted.size();
  if (score.has_bias) wanted.insert(wanted.end(), std::begin(kEurocBias), std::end(kEurocBias));
  auto truth_columns = read_table(truth_path, wanted, truth_options);
  for (double& t : truth_columns[0]) t *= layout->seconds_per_unit;
  const QuatSeries truth = quaternions(truth_columns);
  std::vector<std::string> estimate_names{"time_s", "qw", "qx", "qy", "qz", "heading_sigma_deg"};
  if (score.has_bias) estimate_names.insert(estimate_names.end(), {"bias_x_dps", "bias_y_dps", "bias_z_dps"});
  const auto estimate_columns = read_table(estimates_path, estimate_names, nan_allowed);
  const QuatSeries estimate = quaternions(estimate_columns);
  const std::vector<double>& sigma = estimate_columns[5];
  if (truth.t_s.empty()) return score;

  bool aligned = false;
  Quat align = Quat::Identity();
  std::size_t k = 0;  // the truth row at or before the estimate's time
  for (std::size_t i = 0; i < estimate.t_s.size(); ++i) {
    const double t = estimate.t_s[i];
    if (!estimate.valid[i] || t < truth.t_s.front() - kSameTimeS || t > truth.t_s.back() + kSameTimeS) continue;
    while (k + 1 < truth.t_s.size() && truth.t_s[k + 1] <= t + kSameTimeS) ++k;
    Quat q_true;
    std::size_t nearer = k;
    double w = 0.0;  // how far towards row k + 1
    if (std::abs(truth.t_s[k] - t) <= kSameTimeS) {
      if (!truth.valid[k]) continue;
      q_true = truth.q[k];
    } else {
      if (k + 1 >= truth.t_s.size() || !truth.valid[k] || !truth.valid[k + 1] ||
          truth.t_s[k + 1] - truth.t_s[k] > max_truth_gap_s)
        continue;  // no truth close enough on both sides: not scored rather than guessed
      w = (t - truth.t_s[k]) / (truth.t_s[k + 1] - truth.t_s[k]);
      q_true = truth.q[k].slerp(w, truth.q[k + 1]);
      if (w > 0.5) nearer = k + 1;
    }
    if (score.has_bias) {
      Eigen::Vector3d error_dps;
      for (Eigen::Index a = 0; a < 3; ++a) {
        const auto& b = truth_columns[bias_column + static_cast<std::size_t>(a)];
        const double truth_rad_s = w > 0.0 ? (1.0 - w) * b[k] + w * b[k + 1] : b[k];
        error_dps[a] = estimate_columns[6 + static_cast<std::size_t>(a)][i] - core::rad_to_deg(truth_rad_s);
      }
      if (error_dps.allFinite()) {
        score.bias_sum_sq_dps2 += error_dps.cwiseAbs2();
        score.bias_last_error_dps = error_dps;
        ++score.bias_rows;
      }
    }
    if (!aligned) {
      align = q_true * estimate.q[i].inverse();
      aligned = true;
    }
    const double error = heading_twist_deg(q_true, align * estimate.q[i]);
    const bool inside = std::abs(error) <= 2.0 * sigma[i];
    score.has_sigma = score.has_sigma && std::isfinite(sigma[i]);
    score.all.add(t, error);
    score.within_2sigma += inside;
    score.errors.emplace_back(t, error);
    if (score.has_moving && truth_columns[5][nearer] > 0.5) {
      score.moving.add(t, error);
      score.moving_within_2sigma += inside;
    }
  }
  return score;
}

}  // namespace headingd::app
