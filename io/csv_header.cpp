#include "io/csv_header.hpp"

#include "io/text_fields.hpp"

namespace headingd::drivers {

std::string_view column_name(std::string_view field) {
  field = trim(field);
  return trim(field.substr(0, field.find('[')));
}

std::optional<std::string_view> euroc_header_body(std::string_view trimmed_line) {
  if (trimmed_line.empty() || trimmed_line.front() != '#') return std::nullopt;
  const auto body = trim(trimmed_line.substr(1));
  if (column_name(body.substr(0, body.find(','))) != "timestamp") return std::nullopt;
  return body;
}

std::optional<HeaderLine> read_header_line(LineReader& lines, std::vector<std::string>* comments) {
  std::string_view line;
  while (lines.next(line)) {
    const auto text = trim(line);
    const auto euroc = euroc_header_body(text);
    const bool content = !text.empty() && text.front() != '#';
    lines.count_line(content || euroc);
    if (euroc) return HeaderLine{*euroc, true};
    if (content) return HeaderLine{text, false};
    if (comments && !text.empty()) comments->emplace_back(trim(text.substr(1)));
  }
  return std::nullopt;
}

}  // namespace headingd::drivers
