#include "io/csv_out.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "io/compressed_file.hpp"

namespace headingd::app {
namespace {
constexpr std::size_t kBufferBytes = 1 << 20;
constexpr std::size_t kMaxFieldBytes = 64;
}  // namespace

CsvOut::CsvOut(std::string path) : path_(std::move(path)), buffer_(kBufferBytes) {
  if (path_ == "-") {
    file_ = stdout;
  } else {
    // Estimates and recordings are streamed: readable while they grow (tail -f; a crash keeps all but
    // the last second), so they are written in place rather than renamed into place at the end; a
    // symbolic link planted at the name is refused, never followed (O_NOFOLLOW on the last component).
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0644);
    if (fd < 0 && errno == ELOOP)
      throw OutputError("cannot create " + path_ +
                        ": it is a symbolic link (give the real path; '-' is standard output)");
    if (fd < 0) throw OutputError("cannot create " + path_ + ": " + std::strerror(errno));
    file_ = ::fdopen(fd, "wb");
    if (file_ == nullptr) {
      ::close(fd);
      throw OutputError("cannot create " + path_ + ": " + std::strerror(errno));
    }
    if (drivers::wants_zstd(path_)) {  // "x.csv.zst": compressed as it is written
      file_ = drivers::zstd_writer(file_);
      if (file_ == nullptr) throw OutputError("cannot create " + path_ + ": " + std::strerror(errno));
    }
    owns_file_ = true;
  }
}

CsvOut::~CsvOut() {
  try {
    close();
  } catch (const OutputError&) {
    // Destructors must not throw; callers that care call close() themselves.
  }
}

void CsvOut::reserve(std::size_t bytes) {
  if (used_ + bytes > buffer_.size()) flush();
}

void CsvOut::separator() {
  if (line_started_) buffer_[used_++] = ',';
  line_started_ = true;
}

CsvOut& CsvOut::text(std::string_view value) {
  reserve(value.size() + 1);
  if (value.size() + 1 > buffer_.size()) buffer_.resize(value.size() + 1);
  separator();
  std::memcpy(buffer_.data() + used_, value.data(), value.size());
  used_ += value.size();
  return *this;
}

CsvOut& CsvOut::number(double value, int decimals) {
  reserve(kMaxFieldBytes + 1);
  separator();
  if (!std::isfinite(value)) {
    const std::string_view word = std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
    std::memcpy(buffer_.data() + used_, word.data(), word.size());
    used_ += word.size();
    return *this;
  }
  char* out = buffer_.data() + used_;
  auto result = std::to_chars(out, out + kMaxFieldBytes, value, std::chars_format::fixed, decimals);
  if (result.ec != std::errc{}) {
    result = std::to_chars(out, out + kMaxFieldBytes, value, std::chars_format::scientific, decimals);
  }
  used_ += static_cast<std::size_t>(result.ptr - out);
  return *this;
}

CsvOut& CsvOut::exact(double value) {
  if (!std::isfinite(value)) return number(value, 0);
  reserve(kMaxFieldBytes + 1);
  separator();
  char* out = buffer_.data() + used_;
  auto result = std::to_chars(out, out + kMaxFieldBytes, value, std::chars_format::fixed);
  if (result.ec != std::errc{}) result = std::to_chars(out, out + kMaxFieldBytes, value);  // tiny: exponent form
  used_ += static_cast<std::size_t>(result.ptr - out);
  return *this;
}

CsvOut& CsvOut::integer(std::int64_t value) {
  reserve(kMaxFieldBytes + 1);
  separator();
  char* out = buffer_.data() + used_;
  const auto result = std::to_chars(out, out + kMaxFieldBytes, value);
  used_ += static_cast<std::size_t>(result.ptr - out);
  return *this;
}

void CsvOut::end_line() {
  reserve(1);
  buffer_[used_++] = '\n';
  line_started_ = false;
}

void CsvOut::line(std::string_view whole_line) {
  text(whole_line);
  end_line();
}

void CsvOut::flush() {
  if (file_ == nullptr) return;
  if (used_ > 0 && std::fwrite(buffer_.data(), 1, used_, file_) != used_) {
    const int error = errno;
    used_ = 0;  // what could not be written is gone: a later flush must not fail on it again
    if (error == EPIPE) throw OutputClosed(path_ + ": the reader closed it");
    throw OutputError("cannot write " + path_ + ": " + std::strerror(error));
  }
  used_ = 0;
}

void CsvOut::push() {
  flush();
  if (file_ != nullptr && std::fflush(file_) != 0) {
    if (errno == EPIPE) throw OutputClosed(path_ + ": the reader closed it");
    throw OutputError("cannot write " + path_ + ": " + std::strerror(errno));
  }
}

void CsvOut::close() {
  if (file_ == nullptr) return;
  flush();
  std::FILE* file = file_;
  file_ = nullptr;
  const bool failed = owns_file_ ? std::fclose(file) != 0 : std::fflush(file) != 0;
  if (failed && errno == EPIPE) throw OutputClosed(path_ + ": the reader closed it");
  if (failed) throw OutputError("cannot write " + path_ + ": " + std::strerror(errno));
}

}  // namespace headingd::app
