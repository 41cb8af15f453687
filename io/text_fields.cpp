#include "io/text_fields.hpp"

#include <charconv>
#include <cmath>

namespace headingd::drivers {

std::string_view trim(std::string_view text) {
  constexpr std::string_view kBlank = " \t\r";
  const auto first = text.find_first_not_of(kBlank);
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(kBlank);
  return text.substr(first, last - first + 1);
}

void split_fields(std::string_view line, char separator, Fields& out) {
  out.count = 0;
  out.overflow = false;
  std::size_t start = 0;
  while (true) {
    const auto end = line.find(separator, start);
    const auto field = line.substr(start, end == std::string_view::npos ? line.npos : end - start);
    if (out.count == Fields::kMax) {
      out.overflow = true;
      return;
    }
    out.items[out.count++] = field;
    if (end == std::string_view::npos) return;
    start = end + 1;
  }
}

std::optional<double> parse_double(std::string_view field) {
  field = trim(field);
  if (field.empty()) return std::nullopt;
  // from_chars rejects a leading '+', which some tools write; accept it.
  if (field.front() == '+') field.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc{} || end != field.data() + field.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_int64(std::string_view field) {
  field = trim(field);
  if (field.empty()) return std::nullopt;
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc{} || end != field.data() + field.size()) return std::nullopt;
  return value;
}

}  // namespace headingd::drivers
