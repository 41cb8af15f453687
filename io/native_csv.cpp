#include "io/native_csv.hpp"

#include <cmath>

namespace headingd::app {

RecordingWriter::RecordingWriter(const std::string& path, std::string_view comments, RecordingPrecision precision)
    : out_(path), precision_(precision) {
  while (!comments.empty()) {
    const auto end = comments.find('\n');
    out_.line(comments.substr(0, end));
    comments = end == std::string_view::npos ? std::string_view{} : comments.substr(end + 1);
  }
  out_.text(kNativeTimeColumn);
  for (const auto name : kNativeRateColumns) out_.text(name);
  out_.text(kNativeTempColumn);
  out_.end_line();
}

void RecordingWriter::add(const core::Sample& sample) {
  out_.number(sample.t_s, precision_.time_decimals);
  // Exact: an L3GD20H's multiples of 8.75 mdps and an IIO gyro's raw * scale alike read back
  // as the very doubles the estimator saw.
  for (int axis = 0; axis < 3; ++axis) out_.exact(sample.rate_dps[axis]);
  // A sensor without a temperature channel (many IIO gyros): an empty field, read back as unknown.
  if (std::isnan(sample.temp_c))
    out_.text("");
  else
    out_.number(sample.temp_c, precision_.temp_decimals);
  out_.end_line();
}

void RecordingWriter::comment(std::string_view line) { out_.line(line); }

void RecordingWriter::close() { out_.close(); }

}  // namespace headingd::app
