#include "io/text_fields.hpp"

#include <charconv>
#include <cmath>

namespace headingd::drivers {

std::string_view trim(std::string_view text) {
  // Plain loops: find_first_not_of searches the set once per character, and this runs on
  // every line of a recording.
  std::size_t first = 0;
  std::size_t last = text.size();
  while (first < last && is_blank(text[first])) ++first;
  while (last > first && is_blank(text[last - 1])) --last;
  return text.substr(first, last - first);
}

namespace {

// Plain decimals ("-0.46375", "22.00"), the whole of a recording, without from_chars' general
// machinery: the digits as an integer m and the count of decimals d. When m < 2^53 and d <= 22
// both m and 10^d are exact doubles and one division is correctly rounded (Clinger's fast
// path), so the result is bit for bit what from_chars gives. Anything else (an exponent, more
// digits, "inf", ".5") returns nullptr and goes to from_chars.
const char* parse_plain_decimal(const char* p, const char* end, double& value) {
  static constexpr double kPowers[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr std::uint64_t kExactLimit = std::uint64_t{1} << 53;
  const bool negative = p < end && *p == '-';
  if (negative) ++p;
  std::uint64_t mantissa = 0;
  int digits = 0;
  int decimals = 0;
  const char* start = p;
  for (; p < end && *p >= '0' && *p <= '9' && digits < 19; ++p, ++digits)
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
  if (p == start) return nullptr;
  if (p < end && *p == '.') {
    const char* fraction = ++p;
    for (; p < end && *p >= '0' && *p <= '9' && digits < 19; ++p, ++digits)
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
    decimals = static_cast<int>(p - fraction);
    if (decimals == 0) return nullptr;
  }
  if (p < end && ((*p >= '0' && *p <= '9') || *p == 'e' || *p == 'E' || *p == '.')) return nullptr;
  if (mantissa >= kExactLimit || decimals > 22) return nullptr;
  const double magnitude = static_cast<double>(mantissa) / kPowers[decimals];
  value = negative ? -magnitude : magnitude;
  return p;
}

}  // namespace

const char* scan_double(const char* p, const char* end, double& value) {
  while (p < end && is_blank(*p)) ++p;
  if (p < end && *p == '+') ++p;  // as parse_double
  if (const char* after = parse_plain_decimal(p, end, value)) {
    while (after < end && is_blank(*after)) ++after;
    return after;
  }
  const auto [after, error] = std::from_chars(p, end, value);
  if (error != std::errc{} || after == p || !std::isfinite(value)) return nullptr;
  p = after;
  while (p < end && is_blank(*p)) ++p;
  return p;
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
