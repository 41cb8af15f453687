#pragma once
// Allocation-free helpers for reading CSV text: split a line into fields, trim, parse numbers.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace headingd::drivers {

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
std::string_view trim(std::string_view text);

// Fields of one line, as views into the line. Holds at most kMax; `overflow` says more existed.
struct Fields {
  static constexpr std::size_t kMax = 64;
  std::array<std::string_view, kMax> items{};
  std::size_t count = 0;
  bool overflow = false;
};
void split_fields(std::string_view line, char separator, Fields& out);

// Whole field must be a finite number (surrounding blanks allowed); nullopt otherwise.
std::optional<double> parse_double(std::string_view field);
std::optional<std::int64_t> parse_int64(std::string_view field);
// One number at `p` as parse_double takes a field (blanks around it, a leading '+'), for a
// one-pass scan: where the blanks after it end (the separator, or `end`), or nullptr when no
// finite number starts there.
const char* scan_double(const char* p, const char* end, double& value);

}  // namespace headingd::drivers
