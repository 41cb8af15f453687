#include "tools/plot_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "io/csv_replay.hpp"
#include "io/joined_replay.hpp"
#include "io/line_reader.hpp"
#include "service/exit_codes.hpp"
#include "service/input_errors.hpp"
#include "tools/csv_table.hpp"
#include "tools/gnuplot.hpp"
#include "tools/heading_score.hpp"
#include "tools/orientation_score.hpp"

namespace headingd::app {
namespace {

constexpr std::size_t kMaxPoints = 20000;  // per series: more than a picture's width resolves

std::size_t data_rows(const std::string& path) {
  drivers::LineReader lines(path);
  std::string_view line;
  std::size_t rows = 0;
  while (lines.next(line)) {
    const bool content = !line.empty() && line.front() != '#';
    lines.count_line(content);
    if (content) ++rows;
  }
  return rows > 0 ? rows - 1 : 0;
}

struct TimeAxis {
  double t0 = 0.0, scale = 1.0;
  const char* label = "time [s]";
  double operator()(double t) const { return (t - t0) / scale; }
};

TimeAxis axis_for(double t0, double span_s) {
  if (span_s > 2 * 3600.0) return {t0, 3600.0, "time [h]"};
  if (span_s > 10 * 60.0) return {t0, 60.0, "time [min]"};
  return {t0, 1.0, "time [s]"};
}

void append(std::string& text, std::initializer_list<double> values) {
  char field[32];
  bool first = true;
  for (double v : values) {
    std::snprintf(field, sizeof field, std::isfinite(v) ? "%s%.6g" : "%sNaN", first ? "" : " ", v);
    text += field;
    first = false;
  }
  text += '\n';
}

}  // namespace

int run_plot(const PlotOptions& options) {
  const std::string& out = options.output;
  const bool svg = out.size() > 4 && out.compare(out.size() - 4, 4, ".svg") == 0;
  const bool png = out.size() > 4 && out.compare(out.size() - 4, 4, ".png") == 0;
  if (!svg && !png) {
    std::fprintf(stderr, "headingd: plot: the output must end in .png or .svg\n");
    return kExitUsage;
  }
  std::vector<std::vector<double>> est, truth, rec;
  std::vector<std::pair<double, double>> errors;
  if (const int code = report_input_errors([&] {
        const std::size_t every = std::max<std::size_t>(1, data_rows(options.estimates) / kMaxPoints);
        est = read_table(
            options.estimates,
            {"time_s", "heading_deg", "heading_sigma_deg", "bias_x_dps", "bias_y_dps", "bias_z_dps", "still"},
            {every, false});
        if (options.truth && is_orientation_truth(*options.truth)) {
          // Motion capture: the error as `score` takes it (about the earth's vertical). No truth
          // line beside the heading: the estimate's heading is its z filter's angle, which on a
          // tilted sensor is not the turn about the vertical the truth's heading would be.
          errors = score_orientation(options.estimates, *options.truth).errors;
        } else if (options.truth) {
          truth = read_table(*options.truth, {"time_s", "heading_deg"});
          // The error at full resolution of the estimates, then thinned like every series.
          score_heading(read_columns(options.estimates, "time_s", "heading_deg"), TimeSeries{truth[0], truth[1]},
                        &errors);
        }
        // Any recording replay reads (native or EuRoC, plain or compressed), or those it joined.
        std::unique_ptr<core::SampleSource> source;
        std::size_t rows = 0;
        if (!options.joined.empty()) {
          for (const auto& part : options.joined) rows += data_rows(part);
          source = std::make_unique<drivers::JoinedReplaySource>(options.joined);
        } else if (options.recording) {
          rows = data_rows(*options.recording);
          source = std::make_unique<drivers::CsvReplaySource>(*options.recording);
        }
        if (source) {
          const std::size_t rec_every = std::max<std::size_t>(1, rows / kMaxPoints);
          std::vector<core::Sample> batch(4096);
          rec.assign(2, {});
          std::size_t n = 0;
          while (const std::size_t got = source->read(batch))
            for (std::size_t i = 0; i < got; ++i)
              if (n++ % rec_every == 0) {
                rec[0].push_back(batch[i].t_s);
                rec[1].push_back(batch[i].temp_c);
              }
        }
      }))
    return code;
  if (est[0].size() < 2) {
    std::fprintf(stderr, "headingd: plot: %s has fewer than two estimates\n", options.estimates.c_str());
    return kExitDataError;
  }
  const TimeAxis x = axis_for(est[0].front(), est[0].back() - est[0].front());

  std::string heading, bias, still, truth_text, error_text, temp;
  for (std::size_t i = 0; i < est[0].size(); ++i) {
    const double t = x(est[0][i]), h = est[1][i], two_sigma = 2.0 * est[2][i];
    append(heading, {t, h, h - two_sigma, h + two_sigma});
    append(bias, {t, est[3][i], est[4][i], est[5][i]});
  }
  // Still segments as boxes: start and end of each run of still = 1.
  for (std::size_t i = 0; i < est[0].size();) {
    if (est[6][i] < 0.5) {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < est[0].size() && est[6][i] >= 0.5) ++i;
    append(still, {x(est[0][start]), x(est[0][std::min(i, est[0].size() - 1)])});
  }
  const std::size_t truth_every = std::max<std::size_t>(1, (truth.empty() ? 0 : truth[0].size()) / kMaxPoints);
  if (!truth.empty())
    for (std::size_t i = 0; i < truth[0].size(); i += truth_every) append(truth_text, {x(truth[0][i]), truth[1][i]});
  // The error with the band the estimate claims, at the truth's instants.
  const std::size_t error_every = std::max<std::size_t>(1, errors.size() / kMaxPoints);
  for (std::size_t i = 0, j = 0; i < errors.size(); i += error_every) {
    while (j + 1 < est[0].size() && est[0][j + 1] <= errors[i].first) ++j;
    const double two_sigma = 2.0 * est[2][j];
    append(error_text, {x(errors[i].first), errors[i].second, -two_sigma, two_sigma});
  }
  bool has_temp = false;
  if (!rec.empty())
    for (std::size_t i = 0; i < rec[0].size(); ++i) {
      append(temp, {x(rec[0][i]), rec[1][i]});
      has_temp = has_temp || std::isfinite(rec[1][i]);
    }

  const bool with_truth = !truth.empty();
  const bool with_error = !errors.empty();
  const int panels = with_error ? 3 : 2;
  std::string s = svg ? "set terminal svg size 1200," : "set terminal pngcairo size 1200,";
  s += std::to_string(panels * 300) + " font ',10'\nset encoding utf8\n";
  s += svg ? "set output 'plot.svg'\n" : "set output 'plot.png'\n";
  s += "set multiplot layout " + std::to_string(panels) +
       ",1\nset grid\nset key outside right top\nset autoscale xfix\n";
  s += "set xlabel '" + std::string(x.label) + "'\nset lmargin 12\nset rmargin 22\n";
  const bool has_still = !still.empty();
  // 1. Heading, its band, the truth, the still segments behind.
  s += "set title 'Heading (estimate with its ±2σ band" + std::string(with_truth ? ", and the truth" : "") +
       "; still segments shaded)'\nset ylabel 'heading [deg]'\nset y2range [0:1]\nunset y2tics\n";
  s += "plot ";
  if (has_still)
    s += "'still.dat' using (($1+$2)/2):(1):($2-$1) axes x1y2 with boxes fs solid 0.25 noborder lc rgb '#74c476' title "
         "'still', ";
  s +=
      "'heading.dat' using 1:3:4 with filledcurves fc rgb '#c6dbef' title '±2σ', '' using 1:2 with lines lw 1.5 lc rgb "
      "'#08519c' title 'estimate'";
  if (with_truth) s += ", 'truth.dat' using 1:2 with lines dt 2 lw 1.5 lc rgb 'black' title 'truth'";
  s += "\n";
  // 2. The error against the truth, inside the band the estimate claims.
  if (with_error)
    s += "set title 'Heading error (truth − estimate) and the ±2σ the estimate claims'\nset ylabel 'error [deg]'\n"
         "plot 'error.dat' using 1:3:4 with filledcurves fc rgb '#fdd0a2' title '±2σ', '' using 1:2 with lines lw 1.5 "
         "lc rgb '#d94801' title 'error'\n";
  // 3. The bias per axis, the temperature on the second axis.
  s += "set title 'Gyro bias per axis" + std::string(has_temp ? " and sensor temperature" : "") +
       "'\nset ylabel 'bias [deg/s]'\n";
  // The key below, so that it never sits on the second axis' label.
  if (has_temp) s += "set y2label 'temperature [°C]'\nset y2tics\nset autoscale y2\nset key below horizontal\n";
  s += "plot 'bias.dat' using 1:2 with lines lc rgb '#e41a1c' title 'x', '' using 1:3 with lines lc rgb '#4daf4a' "
       "title 'y', '' using 1:4 with lines lc rgb '#377eb8' title 'z'";
  if (has_temp) s += ", 'temp.dat' using 1:2 axes x1y2 with lines dt 3 lc rgb '#636363' title 'temperature'";
  s += "\nunset multiplot\n";

  std::vector<PlotFile> files = {{"heading.dat", heading}, {"bias.dat", bias}};
  if (has_still) files.push_back({"still.dat", still});
  if (with_truth) files.push_back({"truth.dat", truth_text});
  if (with_error) files.push_back({"error.dat", error_text});
  if (has_temp) files.push_back({"temp.dat", temp});
  if (const auto problem = draw_with_gnuplot(files, s, svg ? "plot.svg" : "plot.png", out)) {
    std::fprintf(stderr, "headingd: plot: %s\n", problem->c_str());
    return kExitCantCreate;
  }
  return kExitOk;
}

}  // namespace headingd::app
