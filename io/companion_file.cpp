#include "io/companion_file.hpp"

#include <string_view>

#include "io/csv_header.hpp"
#include "io/input_error.hpp"
#include "io/line_reader.hpp"
#include "io/native_csv.hpp"
#include "io/text_fields.hpp"

namespace headingd::drivers {
namespace {

bool has_column(const Fields& header, std::string_view name) {
  for (std::size_t i = 0; i < header.count; ++i)
    if (column_name(header.items[i]) == name) return true;
  return false;
}

std::optional<std::string> kind_of_header(const Fields& header) {
  for (const auto rate : app::kNativeRateColumns)
    if (has_column(header, rate)) return std::nullopt;
  // The columns each kind is written with (tools/simulate_command, io/estimates_writer,
  // tools/score_command, app/batch_replay); BROAD's truth files carry `moving` as ours do.
  if (has_column(header, "moving")) return "a truth file";
  if (has_column(header, "heading_deg")) return "an estimates file";
  if (has_column(header, "error_deg")) return "an error series (score --errors)";
  if (has_column(header, "file") && has_column(header, "estimates")) return "a replay summary table";
  return std::nullopt;
}

}  // namespace

std::optional<std::string> companion_kind(const std::string& path) {
  try {
    LineReader lines(path);
    const auto header_line = read_header_line(lines);
    if (!header_line) return std::nullopt;
    Fields header;
    split_fields(header_line->text, ',', header);
    if (!header_line->euroc) return kind_of_header(header);
    // An EuRoC/ASL recording names the gyro's columns; the dataset's other files share the
    // layout (ground truth, cameras, a laser tracker).
    if (has_column(header, "w_RS_S_x")) return std::nullopt;
    if (has_column(header, "q_RS_w")) return "an EuRoC/ASL ground truth";
    return "another EuRoC/ASL sensor's data, no w_RS_S_x";
  } catch (const OpenError&) {
  } catch (const InputError&) {
  }
  return std::nullopt;  // the replay reports what stopped this read
}

}  // namespace headingd::drivers
