#include "io/csv_replay.hpp"

#include <cerrno>
#include <cstring>
#include <limits>

#include "core/units.hpp"
#include "io/csv_header.hpp"
#include "io/native_csv.hpp"

namespace headingd::drivers {
namespace {

constexpr std::string_view kEurocTime = "timestamp";
constexpr std::string_view kEurocRates[3] = {"w_RS_S_x", "w_RS_S_y", "w_RS_S_z"};

std::string shorten(std::string_view text) { return printable(text, 40); }

}  // namespace

CsvReplaySource::CsvReplaySource(std::string path) : path_(path), lines_(std::move(path)) {
  try {
    read_header();
  } catch (...) {
    close();
    throw;
  }
}

CsvReplaySource::CsvReplaySource(std::FILE* file, std::string name) : path_(name), lines_(file, std::move(name)) {
  try {
    read_header();
  } catch (...) {
    close();
    throw;
  }
}

CsvReplaySource::~CsvReplaySource() { close(); }

void CsvReplaySource::close() { lines_.close(); }

std::string CsvReplaySource::describe() const {
  return path_ + (format_ == Format::Euroc ? " (EuRoC/ASL IMU CSV)" : " (headingd CSV)");
}

void CsvReplaySource::fail(std::string problem) const { lines_.fail(std::move(problem)); }

bool CsvReplaySource::next_line(std::string_view& line) { return lines_.next(line); }

void CsvReplaySource::read_header() {
  const auto header = read_header_line(lines_, &comments_);
  if (!header) {
    if (lines_.line_number() == 0) fail("file is empty");
    fail("no header line: expected 'time_s,gx_dps,gy_dps,gz_dps' or an EuRoC '#timestamp [ns],…' line");
  }
  format_ = header->euroc ? Format::Euroc : Format::Native;
  split_fields(header->text, ',', fields_);
  find_columns(fields_);
}

void CsvReplaySource::find_columns(const Fields& header) {
  if (header.overflow) fail("header has more than " + std::to_string(Fields::kMax) + " columns");
  column_names_.clear();
  for (std::size_t i = 0; i < header.count; ++i) column_names_.emplace_back(trim(header.items[i]));
  // Which of two columns of one name holds the data? Neither guess is safe.
  for (std::size_t i = 0; i < column_names_.size(); ++i)
    for (std::size_t j = i + 1; j < column_names_.size(); ++j)
      if (!column_names_[i].empty() && column_name(column_names_[i]) == column_name(column_names_[j]))
        fail("column '" + printable(column_name(column_names_[i]), 60) + "' appears twice in the header (columns " +
             std::to_string(i + 1) + " and " + std::to_string(j + 1) + ")");

  const auto find = [&](std::string_view key) -> std::optional<std::size_t> {
    for (std::size_t i = 0; i < column_names_.size(); ++i)
      if (column_name(column_names_[i]) == key) return i;
    return std::nullopt;
  };
  const auto require = [&](std::string_view key) {
    const auto index = find(key);
    if (!index) {
      std::string have;
      for (const auto& name : column_names_) have += (have.empty() ? "" : ",") + name;
      fail("missing column '" + std::string(key) + "' in header (found: " + printable(have, 200) + ")");
    }
    return *index;
  };

  const bool euroc = format_ == Format::Euroc;
  time_column_ = require(euroc ? kEurocTime : app::kNativeTimeColumn);
  for (int axis = 0; axis < 3; ++axis) {
    rate_columns_[axis] = require(euroc ? kEurocRates[axis] : app::kNativeRateColumns[axis]);
  }
  temp_column_ = euroc ? std::nullopt : find(app::kNativeTempColumn);
  roles_.assign(column_names_.size(), kIgnored);
  roles_[time_column_] = kTime;
  for (int axis = 0; axis < 3; ++axis) roles_[rate_columns_[axis]] = static_cast<std::int8_t>(axis);
  if (temp_column_) roles_[*temp_column_] = kTemp;
}

bool CsvReplaySource::scan_native(std::string_view line, core::Sample& sample) const {
  const char* p = line.data();
  const char* const end = p + line.size();
  sample.temp_c = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t column = 0; column < roles_.size(); ++column) {
    if (column > 0) {
      if (p == end || *p != ',') return false;  // fewer fields than the header
      ++p;
    }
    const std::int8_t role = roles_[column];
    if (role == kIgnored) {
      const auto* comma = static_cast<const char*>(std::memchr(p, ',', static_cast<std::size_t>(end - p)));
      p = comma != nullptr ? comma : end;
      continue;
    }
    const char* field = p;
    while (field < end && is_blank(*field)) ++field;
    if (role == kTemp && (field == end || *field == ',')) {  // empty: no temperature
      p = field;
      continue;
    }
    double value = 0.0;
    p = scan_double(p, end, value);
    if (p == nullptr) return false;
    if (role == kTime)
      sample.t_s = value;
    else if (role == kTemp)
      sample.temp_c = value;
    else
      sample.rate_dps[role] = value;
  }
  return p == end;  // more fields than the header otherwise
}

void CsvReplaySource::parse_line(std::string_view line, core::Sample& sample) {
  if (format_ == Format::Native && scan_native(line, sample)) {
    check_sample(sample);
    return;
  }
  split_fields(line, ',', fields_);
  if (fields_.overflow || fields_.count != column_names_.size()) {
    fail("expected " + std::to_string(column_names_.size()) + " fields, found " +
         (fields_.overflow ? "more than " + std::to_string(Fields::kMax) : std::to_string(fields_.count)));
  }
  const auto number = [&](std::size_t column) {
    const auto value = parse_double(fields_.items[column]);
    if (!value) {
      fail("field '" + column_names_[column] + "' (column " + std::to_string(column + 1) + "): '" +
           shorten(trim(fields_.items[column])) + "' is not a finite number");
    }
    return *value;
  };

  double t_s = 0.0;
  if (format_ == Format::Euroc) {
    const auto ns = parse_int64(fields_.items[time_column_]);
    if (!ns) {
      fail("field '" + column_names_[time_column_] + "' (column " + std::to_string(time_column_ + 1) + "): '" +
           shorten(trim(fields_.items[time_column_])) + "' is not an integer nanosecond count");
    }
    t_s = static_cast<double>(*ns) / 1e9;
    for (int axis = 0; axis < 3; ++axis) sample.rate_dps[axis] = core::rad_to_deg(number(rate_columns_[axis]));
  } else {
    t_s = number(time_column_);
    for (int axis = 0; axis < 3; ++axis) sample.rate_dps[axis] = number(rate_columns_[axis]);
  }
  // No temperature column, or an empty field (a sensor without one): unknown.
  const bool no_temp = !temp_column_ || trim(fields_.items[*temp_column_]).empty();
  sample.temp_c = no_temp ? std::numeric_limits<double>::quiet_NaN() : number(*temp_column_);

  sample.t_s = t_s;
  check_sample(sample);
}

void CsvReplaySource::check_sample(const core::Sample& sample) {
  const double t_s = sample.t_s;
  if (samples_ > 0 && !(t_s > previous_t_s_)) {
    char text[96];
    std::snprintf(text, sizeof text, "time %s: %.9g s is not after the previous %.9g s",
                  t_s < previous_t_s_ ? "goes backwards" : "does not advance", t_s, previous_t_s_);
    fail(text);
  }
  if (!core::plausible(sample)) fail(*core::why_implausible(sample));
  if (samples_ == 0) first_t_s_ = t_s;
  previous_t_s_ = t_s;
}

core::SourceHealth recording_health(std::uint64_t samples, double first_t_s, double last_t_s) {
  core::SourceHealth health;
  health.samples = samples;
  const double span_s = last_t_s - first_t_s;
  if (samples > 1 && span_s > 0) health.rate_hz = static_cast<double>(samples - 1) / span_s;
  return health;
}

core::SourceHealth CsvReplaySource::health() const { return recording_health(samples_, first_t_s_, previous_t_s_); }

std::size_t CsvReplaySource::read(std::span<core::Sample> out) {
  if (pending_error_) {
    const InputError error = *pending_error_;
    pending_error_.reset();
    close();
    throw error;
  }
  std::size_t count = 0;
  std::string_view line;
  try {
    while (count < out.size() && next_line(line)) {
      const auto text = trim(line);
      const bool content = !text.empty() && text.front() != '#';
      lines_.count_line(content);
      if (!content) {  // blank and comment lines
        if (!text.empty()) last_comment_.assign(trim(text.substr(1)));
        continue;
      }
      parse_line(text, out[count]);
      ++count;
      ++samples_;
    }
    if (count == 0 && samples_ == 0 && lines_.is_open()) fail("no samples after the header");
  } catch (const InputError& error) {
    if (count == 0) {
      close();
      throw;
    }
    pending_error_ = error;  // deliver the good samples first
  }
  return count;
}

}  // namespace headingd::drivers
