#include "tools/score_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/csv_out.hpp"
#include "io/input_error.hpp"
#include "service/exit_codes.hpp"
#include "service/input_errors.hpp"
#include "service/standard_output.hpp"
#include "tools/heading_floor.hpp"
#include "tools/heading_score.hpp"
#include "tools/orientation_score.hpp"

namespace headingd::app {

namespace {

void print_row(int width, const std::string& label, const core::HeadingMetrics& m) {
  std::printf("%-*s %10.2f %10.2f %10.2f %12.3f %8.2f\n", width, label.c_str(), m.max_abs_deg(), m.final_abs_deg(),
              m.rms_deg(), m.drift_deg_per_h(), m.hours());
}

int write_errors(const std::string& path, const std::vector<std::pair<double, double>>& errors) {
  try {
    CsvOut out(path);
    out.line("time_h,error_deg");
    double next_s = -1.0;
    for (const auto& [t_s, error_deg] : errors) {
      if (t_s < next_s) continue;
      next_s = std::floor(t_s) + 1.0;
      out.number(t_s / 3600.0, 6).number(error_deg, 4);
      out.end_line();
    }
    out.close();
  } catch (const OutputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitCantCreate;
  }
  return kExitOk;
}

std::string label_of(const ScoreOptions& options) {
  // Unlabelled, the row would start with blanks and the floor's rows read " floor".
  return options.label.empty() ? std::filesystem::path(options.estimates).filename().string() : options.label;
}

void print_header(int width) {
  std::printf("%-*s %10s %10s %10s %12s %8s\n", width, "method", "max|E| deg", "final|E|", "RMS deg", "drift deg/h",
              "hours");
}

double percent(std::uint64_t part, std::uint64_t whole) {
  return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : std::nan("");
}

// Against a motion-capture orientation (tools/orientation_score): every row the truth covers,
// then the rows it marks as moving, then how many lie within twice the estimate's own sigma.
int score_against_orientation(const ScoreOptions& options) {
  if (options.recording) {
    std::fprintf(stderr,
                 "headingd: --recording (the floor) needs a simulator truth (heading_deg, bias_z_dps, moving); %s "
                 "holds an orientation\n",
                 options.truth.c_str());
    return kExitUsage;
  }
  OrientationScore score;
  if (const int code = report_input_errors([&] { score = score_orientation(options.estimates, options.truth); }))
    return code;
  if (score.all.count() == 0) {
    std::fprintf(stderr, "headingd: %s and %s share no time span with a valid orientation\n", options.estimates.c_str(),
                 options.truth.c_str());
    return kExitDataError;
  }
  if (options.errors_output)
    if (const int code = write_errors(*options.errors_output, score.errors)) return code;
  const std::string label = label_of(options);
  const int width = static_cast<int>(std::max<std::size_t>(12, label.size() + (score.has_moving ? 7 : 0)));
  if (options.header) print_header(width);
  print_row(width, label, score.all);
  if (score.has_moving && score.moving.count() > 0) print_row(width, label + " moving", score.moving);
  if (score.has_sigma) {
    std::printf("# %s: |E| <= 2 sigma on %.1f %% of %llu rows", label.c_str(),
                percent(score.within_2sigma, score.all.count()), static_cast<unsigned long long>(score.all.count()));
    if (score.has_moving)
      std::printf(", %.1f %% of the %llu moving", percent(score.moving_within_2sigma, score.moving.count()),
                  static_cast<unsigned long long>(score.moving.count()));
    std::printf("\n");
  }
  if (score.has_bias && score.bias_rows > 0) {
    const Eigen::Vector3d rms = (score.bias_sum_sq_dps2 / static_cast<double>(score.bias_rows)).cwiseSqrt() * 1e3;
    const Eigen::Vector3d last = score.bias_last_error_dps * 1e3;
    std::printf(
        "# %s: bias minus the truth's (mdps) RMS x %.2f y %.2f z %.2f, at the end x %+.2f y %+.2f z %+.2f "
        "(%llu rows)\n",
        label.c_str(), rms.x(), rms.y(), rms.z(), last.x(), last.y(), last.z(),
        static_cast<unsigned long long>(score.bias_rows));
  }
  return finish_standard_output();
}

}  // namespace

int run_score(const ScoreOptions& options) {
  bool orientation = false;
  if (const int code = report_input_errors([&] { orientation = is_orientation_truth(options.truth); })) return code;
  if (orientation) return score_against_orientation(options);
  TimeSeries estimate;
  TimeSeries truth;
  Truth full_truth;
  TimeSeries floor;
  if (const int code = report_input_errors([&] {
        estimate = read_columns(options.estimates, "time_s", "heading_deg");
        if (options.recording) {
          full_truth = read_truth(options.truth);
          truth = full_truth.heading;
          floor = floor_heading(*options.recording, full_truth);
        } else {
          truth = read_columns(options.truth, "time_s", "heading_deg");
        }
      }))
    return code;
  std::vector<std::pair<double, double>> errors;
  const auto metrics = score_heading(estimate, truth, options.errors_output ? &errors : nullptr);
  if (metrics.count() == 0) {
    std::fprintf(stderr, "headingd: %s and %s share no time span\n", options.estimates.c_str(), options.truth.c_str());
    return kExitDataError;
  }
  if (options.errors_output)
    if (const int code = write_errors(*options.errors_output, errors)) return code;
  const std::string label = label_of(options);
  // A label longer than the column pushes the figures right: the column widens to the longest.
  const int width = static_cast<int>(std::max<std::size_t>(12, label.size() + (options.recording ? 7 : 0)));
  if (options.header) print_header(width);
  print_row(width, label, metrics);
  if (options.recording) {
    print_row(width, label + " floor", score_heading(floor, truth));
    // The floor as the reference: its error column is floor - estimate, the estimate's excess.
    print_row(width, label + " excess", score_heading(estimate, floor));
  }
  return finish_standard_output();
}

}  // namespace headingd::app
