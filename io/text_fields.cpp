#include "io/text_fields.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

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

// m / 10^d for m < 2^64 (19 digits, as the shortest round-trip text of a double often needs 17)
// where long double has a 64-bit mantissa (x86's x87): m and 10^d (d <= 27) are exact there and
// the quotient is correctly rounded to 64 bits. Rounding that to a double is then the correct
// rounding unless the 64-bit quotient lies exactly on a halfway point between two doubles (its
// low 11 bits 0x400: there the true quotient may be on either side); that case, with a margin,
// and every other platform go to from_chars. False when not taken.
bool extended_quotient(std::uint64_t mantissa, int decimals, double& value) {
  if constexpr (std::numeric_limits<long double>::digits != 64 || sizeof(long double) < 10) {
    return false;
  } else {
    static constexpr long double kPowers[] = {1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,  1e8L,  1e9L,
                                              1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L,
                                              1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};
    if (decimals > 27) return false;
    const long double quotient = static_cast<long double>(mantissa) / kPowers[decimals];
    if (quotient == 0.0L) {
      value = 0.0;
      return true;
    }
    // The x87 format keeps its 64-bit mantissa, leading bit included, in its first 8 bytes.
    std::uint64_t bits = 0;
    std::memcpy(&bits, &quotient, sizeof bits);
    const std::uint64_t low = bits & 0x7FF;
    if (low >= 0x3FF && low <= 0x401) return false;
    value = static_cast<double>(quotient);
    return true;
  }
}

// Whether the eight characters at p are all digits, and if so their value (most significant
// first), worked out on the eight bytes at once: in a little-endian word the first character
// is the low byte. A byte is a digit when its high nibble is 3 and adding 6 leaves it 3 (a
// carry out of a byte happens only from 0xFA up, which fails the first test anyway). Then the
// digits are paired (10 a + b, no carry: at most 99), the pairs at bytes 0 and 4 weighted by
// 10^6 and 10^2 and those at 2 and 6 by 10^4 and 1 in one multiply each, the sum in the
// upper half of the word.
bool eight_digits(const char* p, std::uint64_t& value) {
  if constexpr (std::endian::native != std::endian::little) {
    return false;
  } else {
    constexpr std::uint64_t kHighNibbles = 0xF0F0F0F0F0F0F0F0;
    constexpr std::uint64_t kZeros = 0x3030303030303030;
    std::uint64_t word = 0;
    std::memcpy(&word, p, sizeof word);
    if ((word & kHighNibbles) != kZeros || ((word + 0x0606060606060606) & kHighNibbles) != kZeros) return false;
    word -= kZeros;
    word = word * 10 + (word >> 8);
    constexpr std::uint64_t kPairs = 0x000000FF000000FF;
    value =
        (((word & kPairs) * (100 + (1'000'000ULL << 32))) + (((word >> 16) & kPairs) * (1 + (10'000ULL << 32)))) >> 32;
    return true;
  }
}

// Plain decimals ("-0.46375", "22.00"), the whole of a recording, without from_chars' general
// machinery: the digits as an integer m and the count of decimals d. When m < 2^53 and d <= 22
// both m and 10^d are exact doubles and one division is correctly rounded (Clinger's fast
// path), so the result is bit for bit what from_chars gives; longer mantissas go through
// extended_quotient. Anything else (an exponent, more digits, "inf", ".5") returns nullptr and
// goes to from_chars.
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
    // A recording's fractions run to 17 digits: eight at a time while they last.
    for (std::uint64_t eight = 0; end - p >= 8 && digits <= 19 - 8 && eight_digits(p, eight); p += 8, digits += 8)
      mantissa = mantissa * 100'000'000 + eight;
    for (; p < end && *p >= '0' && *p <= '9' && digits < 19; ++p, ++digits)
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
    decimals = static_cast<int>(p - fraction);
    if (decimals == 0) return nullptr;
  }
  if (p < end && ((*p >= '0' && *p <= '9') || *p == 'e' || *p == 'E' || *p == '.')) return nullptr;
  double magnitude = 0.0;
  if (mantissa < kExactLimit && decimals <= 22)
    magnitude = static_cast<double>(mantissa) / kPowers[decimals];
  else if (!extended_quotient(mantissa, decimals, magnitude))
    return nullptr;
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
