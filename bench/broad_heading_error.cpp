// Heading error on the BROAD recording as its data README defines it: the rotation angle
// about the vertical of q_true * q_est^-1 (earth frame, tools/orientation_score, which
// `headingd score` uses too), the estimate aligned to the true orientation at the first valid
// sample, RMSE over the samples the dataset marks as moving.
// Also integrates the raw gyro twice for reference: with no bias removal, and with the bias
// taken by hand as the mean of the first rest, and the turn each axis made about the vertical
// (from the truth). For estimates with a heading sigma, the share of
// moving samples within twice it.
// Usage: broad_heading_error TRUTH.csv IMU.csv [LABEL=ESTIMATES.csv ...]
//        (estimates written by `headingd replay --output-rate 0`, one row per IMU sample)
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/attitude_integrator.hpp"
#include "core/units.hpp"
#include "io/csv_replay.hpp"
#include "io/text_fields.hpp"
#include "tools/orientation_score.hpp"

using namespace headingd;
using Quat = Eigen::Quaterniond;

namespace {

struct TruthRow {
  double t_s;
  Quat q;
  bool valid;
  bool moving;
};

constexpr double kOnsetMarginS = 0.5;

// Rows keyed by time in microseconds, so the two files' times meet exactly.
long long key(double t_s) { return std::llround(t_s * 1e6); }

std::vector<TruthRow> read_truth(const std::string& path) {
  std::ifstream in(path);
  std::vector<TruthRow> rows;
  std::string line;
  std::getline(in, line);  // time_s,qw,qx,qy,qz,moving
  drivers::Fields f;
  while (std::getline(in, line)) {
    drivers::split_fields(line, ',', f);
    if (f.count < 6) continue;
    TruthRow row{};
    row.t_s = drivers::parse_double(f.items[0]).value_or(NAN);
    const auto w = drivers::parse_double(f.items[1]), x = drivers::parse_double(f.items[2]),
               y = drivers::parse_double(f.items[3]), z = drivers::parse_double(f.items[4]);
    row.valid = w && x && y && z;
    if (row.valid) row.q = Quat(*w, *x, *y, *z).normalized();
    row.moving = drivers::trim(f.items[5]) == "1";
    rows.push_back(row);
  }
  return rows;
}

// The estimates' attitude and, where the file has one, their heading sigma (NaN otherwise).
std::map<long long, Quat> read_estimates(const std::string& path, std::map<long long, double>* sigmas = nullptr) {
  std::ifstream in(path);
  std::map<long long, Quat> rows;
  std::string line;
  drivers::Fields f;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == 't' || line[0] == '#') continue;
    drivers::split_fields(line, ',', f);
    const auto t = drivers::parse_double(f.items[0]);
    const auto w = drivers::parse_double(f.items[2]), x = drivers::parse_double(f.items[3]),
               y = drivers::parse_double(f.items[4]), z = drivers::parse_double(f.items[5]);
    if (!(t && w && x && y && z)) continue;
    rows.emplace(key(*t), Quat(*w, *x, *y, *z).normalized());
    if (sigmas != nullptr)
      sigmas->emplace(key(*t), f.count > 9 ? drivers::parse_double(f.items[9]).value_or(NAN) : NAN);
  }
  return rows;
}

// Calls `use(key, heading error)` for each sample the dataset marks as moving, the estimate
// aligned to the truth at the first valid sample.
template <typename Use>
void for_each_moving_error(const std::vector<TruthRow>& truth, const std::map<long long, Quat>& estimate, Use use) {
  bool aligned = false;
  Quat align = Quat::Identity();
  for (const auto& row : truth) {
    const auto it = estimate.find(key(row.t_s));
    if (it == estimate.end() || !row.valid) continue;
    if (!aligned) {
      align = row.q * it->second.inverse();
      aligned = true;
    }
    if (row.moving) use(it->first, app::heading_twist_deg(row.q, align * it->second));
  }
}

// RMSE during movement.
double rmse(const std::vector<TruthRow>& truth, const std::map<long long, Quat>& estimate) {
  double sum = 0.0;
  std::size_t n = 0;
  for_each_moving_error(truth, estimate, [&](long long, double e) {
    sum += e * e;
    ++n;
  });
  return n ? std::sqrt(sum / static_cast<double>(n)) : NAN;
}

// The share of moving samples whose heading error lies within twice the estimate's own heading
// sigma: the sigma's honesty on a recording we did not make. NaN where the estimates carry no
// sigma (the paper's methods).
double within_two_sigma(const std::vector<TruthRow>& truth, const std::map<long long, Quat>& estimate,
                        const std::map<long long, double>& sigma) {
  std::size_t inside = 0, n = 0;
  bool has_sigma = true;
  for_each_moving_error(truth, estimate, [&](long long k, double e) {
    const auto s = sigma.find(k);
    if (s == sigma.end()) return;
    has_sigma = has_sigma && std::isfinite(s->second);
    inside += std::abs(e) <= 2.0 * s->second;
    ++n;
  });
  return n && has_sigma ? 100.0 * static_cast<double>(inside) / static_cast<double>(n) : NAN;
}

// Raw gyro integrated from the first sample with a fixed bias.
std::map<long long, Quat> integrate(const std::vector<core::Sample>& samples, const core::Vec3& bias_dps) {
  std::map<long long, Quat> out;
  core::AttitudeIntegrator attitude;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (i > 0) attitude.add(samples[i].rate_dps - bias_dps, samples[i].t_s - samples[i - 1].t_s);
    out.emplace(key(samples[i].t_s), attitude.attitude());
  }
  return out;
}

// The turn each body axis made about the vertical over the recording (deg), from the true
// orientation and the rates less `bias_dps`: what a scale error of that axis multiplies.
core::Vec3 vertical_turn_by_axis(const std::vector<TruthRow>& truth, const std::vector<core::Sample>& samples,
                                 const core::Vec3& bias_dps) {
  std::map<long long, const TruthRow*> by_time;
  for (const auto& row : truth)
    if (row.valid) by_time.emplace(key(row.t_s), &row);
  core::Vec3 turned = core::Vec3::Zero();
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const auto it = by_time.find(key(samples[i - 1].t_s));
    if (it == by_time.end()) continue;
    const core::Vec3 up_in_body = it->second->q.conjugate() * core::Vec3::UnitZ();
    turned += up_in_body.cwiseProduct(samples[i].rate_dps - bias_dps) * (samples[i].t_s - samples[i - 1].t_s);
  }
  return turned;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: broad_heading_error TRUTH.csv IMU.csv [LABEL=ESTIMATES.csv ...]\n");
    return 64;
  }
  const auto truth = read_truth(argv[1]);
  std::vector<core::Sample> samples;
  drivers::CsvReplaySource source(argv[2]);
  std::vector<core::Sample> batch(4096);
  while (const auto n = source.read(batch))
    samples.insert(samples.end(), batch.begin(), batch.begin() + static_cast<long>(n));

  // The first rest: samples before the dataset's first moving mark.
  double first_motion_s = 0.0;
  for (const auto& row : truth) {
    if (row.moving) {
      first_motion_s = row.t_s;
      break;
    }
  }
  core::Vec3 rest_bias = core::Vec3::Zero();
  std::size_t rest_n = 0;
  for (const auto& s : samples) {
    if (s.t_s >= first_motion_s) break;
    rest_bias += s.rate_dps;
    ++rest_n;
  }
  rest_bias /= static_cast<double>(std::max<std::size_t>(rest_n, 1));
  // The same rest less its last half second: the dataset's movement mark can come after the
  // motion has begun (broad-05: y +0.39, z -0.43 dps over that half second), and those rates
  // then sit in the reference's bias.
  core::Vec3 trimmed_bias = core::Vec3::Zero();
  std::size_t trimmed_n = 0;
  for (const auto& s : samples) {
    if (s.t_s >= first_motion_s - kOnsetMarginS) break;
    trimmed_bias += s.rate_dps;
    ++trimmed_n;
  }
  trimmed_bias /= static_cast<double>(std::max<std::size_t>(trimmed_n, 1));

  std::printf("heading RMSE during movement (deg), BROAD trial 05, %zu samples\n", samples.size());
  std::printf("  %-40s %6.2f\n", "raw gyro, no bias removal", rmse(truth, integrate(samples, core::Vec3::Zero())));
  std::printf("  %-40s %6.2f   (bias %.3f %.3f %.3f dps from %.1f s of rest)\n", "raw gyro, bias of first rest by hand",
              rmse(truth, integrate(samples, rest_bias)), rest_bias.x(), rest_bias.y(), rest_bias.z(),
              static_cast<double>(rest_n) / 285.714);
  std::printf("  %-40s %6.2f   (bias %.3f %.3f %.3f dps)\n", "raw gyro, same rest less its last 0.5 s",
              rmse(truth, integrate(samples, trimmed_bias)), trimmed_bias.x(), trimmed_bias.y(), trimmed_bias.z());
  const core::Vec3 turned = vertical_turn_by_axis(truth, samples, trimmed_bias);
  std::printf("  (turn about the vertical by axis, from the truth: x %.0f, y %.0f, z %.0f deg)\n", turned.x(),
              turned.y(), turned.z());
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto eq = arg.find('=');
    const std::string label = "headingd " + arg.substr(0, eq);
    std::map<long long, double> sigmas;
    const auto estimate = read_estimates(arg.substr(eq + 1), &sigmas);
    const double honest = within_two_sigma(truth, estimate, sigmas);
    if (std::isfinite(honest))
      std::printf("  %-40s %6.2f   (|E| <= 2 sigma on %.1f %% of the moving samples)\n", label.c_str(),
                  rmse(truth, estimate), honest);
    else
      std::printf("  %-40s %6.2f\n", label.c_str(), rmse(truth, estimate));
  }
  return 0;
}
