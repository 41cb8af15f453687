#pragma once
// Named columns of a CSV with '#' comments and a header line (estimates, truth, recordings;
// plain or compressed), with the recording reader's discipline: bounded lines, a truncated last
// line, a duplicated column, a missing one or time going backwards is an error naming file and line.
#include <string>
#include <vector>

namespace headingd::app {

struct TableOptions {
  std::size_t every = 1;         // keep every n-th row (plots of long files)
  bool empty_is_nan = false;     // an empty field is NaN (a recording without temperature), else an error
  bool nan_text_is_nan = false;  // "nan" is NaN (motion capture that lost track), else an error
  // A '#' line naming the columns before any other is the header, as EuRoC/ASL files have it
  // ("#timestamp [ns],q_RS_w [],…"): names compared without the units in brackets.
  bool comment_header = false;
};

// The names in the header line (trimmed; an EuRoC/ASL '#timestamp' line's without their units).
// Throws drivers::InputError/OpenError.
std::vector<std::string> header_columns(const std::string& path);

// columns[0] is the time column, which must advance; returns one vector per name.
std::vector<std::vector<double>> read_table(const std::string& path, const std::vector<std::string>& names,
                                            const TableOptions& options = {});

}  // namespace headingd::app
