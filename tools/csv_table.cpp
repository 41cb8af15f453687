#include "tools/csv_table.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "io/csv_header.hpp"
#include "io/line_reader.hpp"
#include "io/text_fields.hpp"

namespace headingd::app {

std::vector<std::string> header_columns(const std::string& path) {
  drivers::LineReader lines(path);
  const auto header = drivers::read_header_line(lines);
  if (!header) lines.fail("no header line");
  drivers::Fields fields;
  drivers::split_fields(header->text, ',', fields);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < fields.count; ++i) names.emplace_back(drivers::column_name(fields.items[i]));
  return names;
}

std::vector<std::vector<double>> read_table(const std::string& path, const std::vector<std::string>& names,
                                            const TableOptions& options) {
  drivers::LineReader lines(path);
  std::vector<std::vector<double>> columns(names.size());
  std::vector<std::optional<std::size_t>> index(names.size());
  bool have_header = false;
  std::size_t width = 0;
  std::uint64_t row = 0;
  double last_t = -std::numeric_limits<double>::infinity();
  std::string_view line;
  drivers::Fields fields;
  while (lines.next(line)) {
    const auto text = drivers::trim(line);
    const auto euroc = !have_header && options.comment_header ? drivers::euroc_header_body(text) : std::nullopt;
    const bool content = !text.empty() && text.front() != '#';
    lines.count_line(content || euroc);  // a file of nothing but newlines is refused, not read for minutes
    if (!content && !euroc) continue;
    drivers::split_fields(euroc ? *euroc : text, ',', fields);
    if (fields.overflow) lines.fail("more than " + std::to_string(drivers::Fields::kMax) + " fields");
    if (!have_header) {
      have_header = true;
      width = fields.count;
      for (std::size_t i = 0; i < fields.count; ++i)
        for (std::size_t k = 0; k < names.size(); ++k) {
          if ((euroc ? drivers::column_name(fields.items[i]) : drivers::trim(fields.items[i])) != names[k]) continue;
          if (index[k])
            lines.fail("column '" + names[k] + "' appears twice in the header (columns " +
                       std::to_string(*index[k] + 1) + " and " + std::to_string(i + 1) + ")");
          index[k] = i;
        }
      for (std::size_t k = 0; k < names.size(); ++k)
        if (!index[k]) lines.fail("header lacks '" + names[k] + "' (found: " + drivers::printable(text, 200) + ")");
      continue;
    }
    if (fields.count != width)
      lines.fail("expected " + std::to_string(width) + " fields, found " + std::to_string(fields.count));
    const auto t = drivers::parse_double(fields.items[*index[0]]);
    if (!t) lines.fail("time is not a finite number: '" + drivers::printable(text, 80) + "'");
    if (!(*t > last_t)) lines.fail("time does not advance");
    last_t = *t;
    if (row++ % options.every != 0) continue;
    columns[0].push_back(*t);
    for (std::size_t k = 1; k < names.size(); ++k) {
      const auto field = drivers::trim(fields.items[*index[k]]);
      const auto value = drivers::parse_double(field);
      const bool nan_text = options.nan_text_is_nan && (field == "nan" || field == "NaN" || field == "NAN");
      if (!value && !(options.empty_is_nan && field.empty()) && !nan_text)
        lines.fail("'" + names[k] + "' is not a finite number: '" + drivers::printable(text, 80) + "'");
      columns[k].push_back(value ? *value : std::numeric_limits<double>::quiet_NaN());
    }
  }
  if (!have_header) lines.fail("no header line");
  return columns;
}

}  // namespace headingd::app
