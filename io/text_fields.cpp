#include "io/text_fields.hpp"

#include <array>
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

// Powers of ten that are exact doubles (10^22 is the last).
constexpr double kExactPowers[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                   1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// a * b = p + e exactly (Dekker's product: each factor split into halves of 26 and 27 bits, whose
// products are exact), or by one fused multiply-add where the target has one.
struct Halves {
  double hi = 0.0, lo = 0.0;
};
Halves halves(double a) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double hi = c - (c - a);
  return {hi, a - hi};
}
double product_error(double a, const Halves& b, double p) {
#if defined(__FMA__)
  return std::fma(a, b.hi + b.lo, -p);
#else
  const Halves h = halves(a);
  return ((h.hi * b.hi - p) + h.hi * b.lo + h.lo * b.hi) + h.lo * b.lo;
#endif
}

// 1 / 10^d as hi + lo to about 106 bits, hi split for Dekker's product: lo = (1 - hi 10^d) / 10^d,
// whose numerator is exact (hi 10^d = p + e exactly, and 1 - p is exact as p is near 1).
struct Reciprocal {
  Halves hi;
  double lo = 0.0;
};
const Reciprocal& reciprocal_of_ten_to(int decimals) {
  static const auto table = [] {
    std::array<Reciprocal, std::size(kExactPowers)> out{};
    for (std::size_t d = 0; d < out.size(); ++d) {
      const double power = kExactPowers[d];
      const double hi = 1.0 / power;
      const double p = hi * power;
      const double e = product_error(power, halves(hi), p);
      out[d] = {halves(hi), ((1.0 - p) - e) / power};
    }
    return out;
  }();
  return table[static_cast<std::size_t>(decimals)];
}

// m / 10^d for 2^53 <= m < 2^64 (the shortest round-trip text of a double often has 17 digits),
// d <= 22, without a division: m = mh + ml (mh the nearest double, |ml| <= 2^10, exact),
// m / 10^d = mh rh + (e + mh rl + ml rh) with mh rh = p + e exactly and 1/10^d = rh + rl. The sum
// is within about 2^-94 of the quotient, relative, so its rounding to a double is the quotient's
// unless the quotient lies within that of a halfway point: the rounding's own error (Fast2Sum)
// near half an ulp, or a power of two (where the ulp changes), goes to from_chars. False then.
bool reciprocal_quotient(std::uint64_t mantissa, int decimals, double& value) {
  if (decimals >= static_cast<int>(std::size(kExactPowers))) return false;
  const Reciprocal& r = reciprocal_of_ten_to(decimals);
  const auto high = static_cast<double>(mantissa);  // < 1e19 < 2^64: back to an integer exactly
  const auto low = static_cast<double>(static_cast<std::int64_t>(mantissa - static_cast<std::uint64_t>(high)));
  const double rh = r.hi.hi + r.hi.lo;
  const double p = high * rh;
  const double correction = product_error(high, r.hi, p) + (high * r.lo + low * rh);
  const double sum = p + correction;
  const double error = correction - (sum - p);  // exact: |p| >= |correction|
  std::uint64_t bits = 0;
  std::memcpy(&bits, &sum, sizeof bits);
  constexpr std::uint64_t kFraction = (std::uint64_t{1} << 52) - 1;
  if ((bits & kFraction) == 0) return false;
  const std::uint64_t power_bits = bits & ~kFraction & ~(std::uint64_t{1} << 63);
  double power = 0.0;  // 2^exponent of sum
  std::memcpy(&power, &power_bits, sizeof power);
  const double half_ulp = power * 0x1p-53;
  if (std::abs(std::abs(error) - half_ulp) <= power * 0x1p-80) return false;
  value = sum;
  return true;
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
// reciprocal_quotient. Anything else (an exponent, more digits, "inf", ".5") returns nullptr and
// goes to from_chars.
const char* parse_plain_decimal(const char* p, const char* end, double& value) {
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
    magnitude = static_cast<double>(mantissa) / kExactPowers[decimals];
  else if (!reciprocal_quotient(mantissa, decimals, magnitude))
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
