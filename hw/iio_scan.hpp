#pragma once
// How one scan of a Linux IIO buffer is laid out, from the sysfs descriptors the kernel gives
// for each enabled channel (Documentation/ABI/testing/sysfs-bus-iio, "scan_elements"):
// `<channel>_index` orders the channels, `<channel>_type` says "[be|le]:[s|u]bits/storagebits[Xrepeat]>>shift".
// Each channel sits at the next offset that is a multiple of its own storage size, and the scan
// is padded to a multiple of the largest one — the kernel's rule (iio_compute_scan_bytes).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace headingd::drivers::iio {

struct ChannelType {
  bool big_endian = false;
  bool is_signed = false;
  unsigned bits = 0;          // meaningful bits
  unsigned storage_bits = 0;  // 8, 16, 32 or 64
  unsigned repeat = 1;
  unsigned shift = 0;
  std::size_t storage_bytes() const { return storage_bits / 8 * repeat; }
};

// Parses a `_type` descriptor such as "le:s16/16>>0" or "be:u12/16X3>>4"; empty on anything
// else, with `why` saying what is wrong.
std::optional<ChannelType> parse_channel_type(const std::string& text, std::string& why);

struct ScanChannel {
  std::string name;  // "in_anglvel_x", "in_timestamp", ...
  unsigned index = 0;
  ChannelType type;
  std::size_t offset = 0;  // bytes from the start of the scan
};

class ScanLayout {
 public:
  // Orders the channels by index and places them; throws std::invalid_argument when two share
  // an index.
  explicit ScanLayout(std::vector<ScanChannel> channels);
  std::size_t scan_bytes() const { return scan_bytes_; }
  const std::vector<ScanChannel>& channels() const { return channels_; }
  // The position of a channel by name, or nothing.
  const ScanChannel* find(const std::string& name) const;
  // Human-readable: "in_anglvel_x le:s16/16>>0 @0, ... (16 bytes)".
  std::string describe() const;

 private:
  std::vector<ScanChannel> channels_;
  std::size_t scan_bytes_ = 0;
};

// The channel's (first) value in `scan`: byte order, shift, mask and sign applied.
std::int64_t decode(const ScanChannel& channel, std::span<const std::uint8_t> scan);

// The inverse, for fakes and tests: writes `value` into `scan` as the channel stores it.
void encode(const ScanChannel& channel, std::int64_t value, std::span<std::uint8_t> scan);

}  // namespace headingd::drivers::iio
