#pragma once
// The lines of a text file, as every reader of ours takes them: through a fixed buffer (the
// longest line is bounded, nothing is allocated per line), a UTF-8 byte-order mark at the
// start skipped, a last line without its newline reported as truncated (a file cut short or
// still being written), and a directory refused at open as what it is.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace headingd::drivers {

class LineReader {
 public:
  static constexpr std::size_t kMaxLineBytes = 1 << 20;

  // Throws OpenError (missing, unreadable, a directory).
  explicit LineReader(std::string path);
  // An already open stream (a pipe, fmemopen in the fuzzers); takes ownership of it.
  LineReader(std::FILE* file, std::string name);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line without its newline (valid until the next call); false at the end. Throws
  // InputError for an over-long line, a read error or a truncated last line.
  bool next(std::string_view& line);
  std::uint64_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }
  bool is_open() const { return file_ != nullptr; }
  // How much of a plain file has been taken, 0..1; nothing for a stream or a compressed file
  // (whose uncompressed size is not known up front).
  std::optional<double> fraction_read() const;
  void close();
  // An InputError at the current line.
  [[noreturn]] void fail(std::string problem) const;
  // Callers skip blank and comment lines; this counts them and refuses a run of more than
  // kMaxSkippedRun (a compressed file of nothing but newlines expands ~30,000-fold and would keep
  // a reader busy for minutes; no recording has such a run). `content` resets the count.
  static constexpr std::uint64_t kMaxSkippedRun = 100000;
  void count_line(bool content);

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool eof_ = false;
  std::uint64_t line_number_ = 0;
  std::int64_t size_bytes_ = -1;  // a plain regular file's size, else -1
  std::uint64_t bytes_in_ = 0;    // read from the file (after decompression) so far
  std::uint64_t skipped_run_ = 0;
};

// Text from a file for an error message: control and non-ASCII bytes as \xHH, at most
// `max_bytes` of it, so a binary file cannot garble the terminal or the journal.
std::string printable(std::string_view text, std::size_t max_bytes = 40);

}  // namespace headingd::drivers
