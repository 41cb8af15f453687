#include "io/line_reader.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "io/compressed_file.hpp"
#include "io/input_error.hpp"

namespace headingd::drivers {
namespace {

constexpr std::string_view kBom = "\xEF\xBB\xBF";

void refuse_directory(std::FILE* file, const std::string& path) {
  struct stat info {};
  if (::fstat(::fileno(file), &info) == 0 && S_ISDIR(info.st_mode)) {
    std::fclose(file);
    throw OpenError("cannot read " + path + ": it is a directory");
  }
}

}  // namespace

LineReader::LineReader(std::string path) : path_(std::move(path)), buffer_(kMaxLineBytes) {
  bool compressed = false;
  file_ = open_for_reading(path_, &compressed);  // zstd and gzip decompressed, by magic number
  if (file_ == nullptr) throw OpenError("cannot open " + path_ + ": " + std::strerror(errno));
  refuse_directory(file_, path_);  // (a directory is not wrapped: its descriptor is there to see)
  // For the progress bar: a plain file's size (by name: a wrapped stream has no descriptor).
  struct stat info {};
  if (!compressed && ::stat(path_.c_str(), &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0)
    size_bytes_ = static_cast<std::int64_t>(info.st_size);
}

LineReader::LineReader(std::FILE* file, std::string name)
    : path_(std::move(name)), file_(file), buffer_(kMaxLineBytes) {
  if (file_ == nullptr) throw OpenError("cannot read " + path_ + ": no stream");
  file_ = decompressing(file_);
  if (file_ == nullptr) throw OpenError("cannot read " + path_ + ": " + std::strerror(errno));
  refuse_directory(file_, path_);
}

LineReader::~LineReader() { close(); }

void LineReader::close() {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
  }
}

std::optional<double> LineReader::fraction_read() const {
  if (size_bytes_ <= 0 || file_ == nullptr) return std::nullopt;
  const auto taken = static_cast<double>(bytes_in_) - static_cast<double>(end_ - begin_);
  return std::clamp(taken / static_cast<double>(size_bytes_), 0.0, 1.0);
}

void LineReader::count_line(bool content) {
  if (content) {
    skipped_run_ = 0;
    return;
  }
  if (++skipped_run_ > kMaxSkippedRun)
    fail("more than " + std::to_string(kMaxSkippedRun) + " blank or comment lines in a row: not a recording");
}

void LineReader::fail(std::string problem) const { throw InputError(path_, line_number_, std::move(problem)); }

bool LineReader::next(std::string_view& line) {
  while (true) {
    const char* start = buffer_.data() + begin_;
    const auto* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
    if (newline != nullptr) {
      line = std::string_view(start, static_cast<std::size_t>(newline - start));
      begin_ += line.size() + 1;
      if (line_number_++ == 0 && line.substr(0, kBom.size()) == kBom) line.remove_prefix(kBom.size());
      return true;
    }
    if (eof_ || file_ == nullptr) {
      if (begin_ == end_) return false;
      begin_ = end_;
      ++line_number_;
      fail("the last line has no newline: the file is truncated, or still being written");
    }
    // Move the partial line to the front and fill the rest of the buffer.
    const std::size_t partial = end_ - begin_;
    if (partial == buffer_.size()) {
      ++line_number_;
      fail("line longer than " + std::to_string(buffer_.size()) + " bytes");
    }
    std::memmove(buffer_.data(), start, partial);
    begin_ = 0;
    end_ = partial;
    const std::size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_);
    end_ += got;
    bytes_in_ += got;
    if (got == 0) {
      if (std::ferror(file_) != 0) {
        const std::string why = decompression_error();
        ++line_number_;  // the line it was reading
        fail(why.empty() ? std::string("read error: ") + std::strerror(errno) : why);
      }
      eof_ = true;
    }
  }
}

std::string printable(std::string_view text, std::size_t max_bytes) {
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max_bytes; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  if (text.size() > max_bytes) out += "...";
  return out;
}

}  // namespace headingd::drivers
