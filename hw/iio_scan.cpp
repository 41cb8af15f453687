#include "hw/iio_scan.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>

namespace headingd::drivers::iio {
namespace {

// Reads an unsigned decimal at `text[pos]`, advancing `pos`.
bool number_at(const std::string& text, std::size_t& pos, unsigned& value) {
  const char* begin = text.data() + pos;
  const char* end = text.data() + text.size();
  const auto [next, error] = std::from_chars(begin, end, value);
  if (error != std::errc{} || next == begin) return false;
  pos = static_cast<std::size_t>(next - text.data());
  return true;
}

bool literal_at(const std::string& text, std::size_t& pos, const char* literal) {
  const std::string_view want(literal);
  if (text.compare(pos, want.size(), want) != 0) return false;
  pos += want.size();
  return true;
}

}  // namespace

std::optional<ChannelType> parse_channel_type(const std::string& raw, std::string& why) {
  std::string text = raw;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  ChannelType type;
  std::size_t pos = 0;
  if (literal_at(text, pos, "be:"))
    type.big_endian = true;
  else if (!literal_at(text, pos, "le:")) {
    why = "does not start with be: or le:";
    return std::nullopt;
  }
  if (literal_at(text, pos, "s"))
    type.is_signed = true;
  else if (!literal_at(text, pos, "u")) {
    why = "has no s or u after the byte order";
    return std::nullopt;
  }
  if (!number_at(text, pos, type.bits) || !literal_at(text, pos, "/") || !number_at(text, pos, type.storage_bits)) {
    why = "has no bits/storagebits";
    return std::nullopt;
  }
  if (literal_at(text, pos, "X") && !number_at(text, pos, type.repeat)) {
    why = "has X without a repeat count";
    return std::nullopt;
  }
  if (!literal_at(text, pos, ">>") || !number_at(text, pos, type.shift) || pos != text.size()) {
    why = "does not end with >>shift";
    return std::nullopt;
  }
  const unsigned s = type.storage_bits;
  if (s != 8 && s != 16 && s != 32 && s != 64) {
    why = "has storage bits " + std::to_string(s) + " (8, 16, 32 or 64 expected)";
    return std::nullopt;
  }
  if (type.bits == 0 || type.bits + type.shift > s || type.repeat == 0 || type.repeat > 16) {
    why = "has bits, shift or repeat that do not fit its storage";
    return std::nullopt;
  }
  return type;
}

ScanLayout::ScanLayout(std::vector<ScanChannel> channels) : channels_(std::move(channels)) {
  std::sort(channels_.begin(), channels_.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  std::size_t largest = 1;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    if (i > 0 && channels_[i].index == channels_[i - 1].index)
      throw std::invalid_argument(channels_[i].name + " and " + channels_[i - 1].name + " share scan index " +
                                  std::to_string(channels_[i].index));
    const std::size_t length = channels_[i].type.storage_bytes();
    scan_bytes_ = (scan_bytes_ + length - 1) / length * length;
    channels_[i].offset = scan_bytes_;
    scan_bytes_ += length;
    largest = std::max(largest, length);
  }
  scan_bytes_ = (scan_bytes_ + largest - 1) / largest * largest;
}

const ScanChannel* ScanLayout::find(const std::string& name) const {
  for (const auto& c : channels_)
    if (c.name == name) return &c;
  return nullptr;
}

std::string ScanLayout::describe() const {
  std::string text;
  for (const auto& c : channels_) {
    if (!text.empty()) text += ", ";
    text += c.name + " " + (c.type.big_endian ? "be:" : "le:") + (c.type.is_signed ? "s" : "u") +
            std::to_string(c.type.bits) + "/" + std::to_string(c.type.storage_bits) +
            (c.type.repeat > 1 ? "X" + std::to_string(c.type.repeat) : "") + ">>" + std::to_string(c.type.shift) +
            " @" + std::to_string(c.offset);
  }
  return text + " (" + std::to_string(scan_bytes_) + " bytes per scan)";
}

std::int64_t decode(const ScanChannel& channel, std::span<const std::uint8_t> scan) {
  const auto& t = channel.type;
  const std::size_t bytes = t.storage_bits / 8;
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < bytes; ++i) {
    const std::size_t at = t.big_endian ? i : bytes - 1 - i;
    word = (word << 8) | scan[channel.offset + at];
  }
  word >>= t.shift;
  if (t.bits < 64) word &= (std::uint64_t{1} << t.bits) - 1;
  if (t.is_signed && t.bits < 64 && (word >> (t.bits - 1)) != 0) word |= ~((std::uint64_t{1} << t.bits) - 1);
  return static_cast<std::int64_t>(word);
}

void encode(const ScanChannel& channel, std::int64_t value, std::span<std::uint8_t> scan) {
  const auto& t = channel.type;
  const std::size_t bytes = t.storage_bits / 8;
  std::uint64_t word = static_cast<std::uint64_t>(value);
  if (t.bits < 64) word &= (std::uint64_t{1} << t.bits) - 1;
  if (t.shift < 64) word <<= t.shift;
  for (std::size_t i = 0; i < bytes; ++i) {
    const std::size_t at = t.big_endian ? bytes - 1 - i : i;
    scan[channel.offset + at] = static_cast<std::uint8_t>(word & 0xFFu);
    word >>= 8;
  }
}

}  // namespace headingd::drivers::iio
