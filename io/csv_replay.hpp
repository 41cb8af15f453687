#pragma once
// Replays a recorded IMU file as a sample source. Two layouts, told apart by the header:
//  - native:  optional '#' comment lines, then `time_s,gx_dps,gy_dps,gz_dps[,temp_c]`
//             (columns found by name, in any order, extra columns ignored);
//  - EuRoC/ASL: `#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y …,w_RS_S_z …[,a_RS_S_…]`.
// Streams through a fixed buffer: no allocation per line, numbers parsed with from_chars.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/sample_source.hpp"
#include "io/input_error.hpp"
#include "io/line_reader.hpp"
#include "io/text_fields.hpp"

namespace headingd::drivers {

class CsvReplaySource final : public core::SampleSource {
 public:
  enum class Format { Native, Euroc };

  // Opens the file and reads its header. Throws OpenError or InputError.
  explicit CsvReplaySource(std::string path);
  // Reads an already open stream (a pipe, fmemopen in the fuzzers); takes ownership of it.
  CsvReplaySource(std::FILE* file, std::string name);
  ~CsvReplaySource() override;
  CsvReplaySource(const CsvReplaySource&) = delete;
  CsvReplaySource& operator=(const CsvReplaySource&) = delete;

  std::size_t read(std::span<core::Sample> out) override;
  void close() override;
  std::string describe() const override;
  core::SourceHealth health() const override;

  Format format() const { return format_; }
  std::optional<double> fraction_read() const { return lines_.fraction_read(); }
  bool has_temperature() const { return temp_column_.has_value(); }
  // The '#' comment lines before the header (provenance), without the '#'.
  const std::vector<std::string>& comments() const { return comments_; }
  // The last '#' line after the header read so far, without the '#' ("" if none): at the end of
  // a recording, the line a recorder closed it with.
  const std::string& last_comment() const { return last_comment_; }

 private:
  bool next_line(std::string_view& line);
  void read_header();
  void find_columns(const Fields& header);
  void parse_line(std::string_view line, core::Sample& sample);
  // The common case in one pass (a native line whose fields are all well formed): false
  // sends the line to the field-by-field parse, which names what is wrong.
  bool scan_native(std::string_view line, core::Sample& sample) const;
  // Time after the previous sample's, values within what a gyro can give.
  void check_sample(const core::Sample& sample);
  [[noreturn]] void fail(std::string problem) const;

  std::string path_;
  LineReader lines_;

  Format format_ = Format::Native;
  std::vector<std::string> column_names_;
  std::vector<std::string> comments_;
  std::string last_comment_;
  std::size_t time_column_ = 0;
  std::size_t rate_columns_[3] = {0, 0, 0};
  std::optional<std::size_t> temp_column_;
  // What each column holds, for scan_native: an axis 0..2, or one of these.
  static constexpr std::int8_t kIgnored = -1, kTime = 3, kTemp = 4;
  std::vector<std::int8_t> roles_;
  Fields fields_;

  std::uint64_t samples_ = 0;
  double previous_t_s_ = 0.0;
  double first_t_s_ = 0.0;
  std::optional<InputError> pending_error_;
};

// A recording's health: its samples and the rate they span (0 until two are read).
core::SourceHealth recording_health(std::uint64_t samples, double first_t_s, double last_t_s);

}  // namespace headingd::drivers
