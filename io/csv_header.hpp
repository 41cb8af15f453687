#pragma once
// The header line of a CSV as every reader of ours finds it: the first line that is neither
// blank nor a '#' comment, or, before it, an EuRoC/ASL comment line naming the columns
// ("#timestamp [ns],w_RS_S_x [rad s^-1],…"). Column names are compared without the unit EuRoC
// puts after them in brackets. One place, so that the replay, the companion-file test and the
// table reader of `score`/`plot` cannot disagree on what a header is.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/line_reader.hpp"

namespace headingd::drivers {

// "w_RS_S_x [rad s^-1]" -> "w_RS_S_x"; any field trimmed.
std::string_view column_name(std::string_view field);

// The body of an EuRoC/ASL header line (a trimmed line starting '#', its first column
// "timestamp"), without the '#'; nothing for any other line.
std::optional<std::string_view> euroc_header_body(std::string_view trimmed_line);

struct HeaderLine {
  std::string_view text;  // the columns, comma-separated (valid until the reader moves on)
  bool euroc = false;     // found as an EuRoC/ASL '#timestamp' comment
};

// Reads up to and including the header line; the comments before it (without '#', trimmed)
// go to `comments` when given. Nothing when the file ends first. Throws what LineReader throws.
std::optional<HeaderLine> read_header_line(LineReader& lines, std::vector<std::string>* comments = nullptr);

}  // namespace headingd::drivers
